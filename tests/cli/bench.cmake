# hipfai bench collision: a --quick run writes the report, CSV and plots; bad options fail with one line.
hipfai_cli_test(NAME bench_collision_quick EXIT 0
                COMMAND bench collision --quick --out @TMP@/bench)
# A benchmark run (40 s on 2 cores): "long", run with scripts/test --long.
set_tests_properties(cli.bench_collision_quick PROPERTIES LABELS "cli;long")
hipfai_cli_test(NAME bench_collision_bad_threads EXIT nonzero STDERR "threads"
                COMMAND bench collision --quick --threads 9 --out @TMP@/bench)
# hipfai bench radial: the quick probe on the smallest scenario (prints its table; no files), and
# a level outside the scenario's range (accepted by the option's 0..8 check, refused by the probe).
hipfai_cli_test(NAME bench_radial_smallest EXIT 0
                COMMAND bench radial --scenario sphere_cube --level 2 --threads 1 --repeats 1)
hipfai_cli_test(NAME bench_radial_bad_level EXIT nonzero
                STDERR "^hipfai: error: bench radial: --level must be 2\\.\\.8 for sphere_cube$"
                COMMAND bench radial --scenario sphere_cube --level 1)
hipfai_cli_test(NAME bench_radial_bad_scenario EXIT nonzero STDERR "--scenario: torus not in"
                COMMAND bench radial --scenario torus)
# hipfai bench striking: the quick probe of the one-pass cylindrical query on the coarsest striking
# hip (prints its table, fails if the angular walk and every candidate disagree), and bad options.
hipfai_cli_test(NAME bench_striking_coarsest EXIT 0
                COMMAND bench striking --scenario hip --level 0 --threads 2 --repeats 1)
hipfai_cli_test(NAME bench_striking_bad_scenario EXIT nonzero STDERR "--scenario: torus not in"
                COMMAND bench striking --scenario torus)
hipfai_cli_test(NAME bench_striking_missing_bones EXIT nonzero STDERR "real-bones"
                COMMAND bench striking --scenario real_ct --real-bones @TMP@/no-such-folder)
