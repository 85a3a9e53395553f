hipfai_cli_test(NAME help EXIT 0 COMMAND --help)
hipfai_cli_test(NAME unknown_subcommand EXIT nonzero COMMAND no-such-command)
