# hipfai generate: one coarse hip with figures; bad options fail at parse time with one line.
hipfai_cli_test(NAME generate_one EXIT 0
                COMMAND generate --ce-deg 30 --alpha-deg 60 --edge-mm 5 --figures --out @TMP@/hip)
hipfai_cli_test(NAME generate_ce_out_of_range EXIT nonzero STDERR "ce-deg"
                COMMAND generate --ce-deg 60 --out @TMP@/hip)
hipfai_cli_test(NAME generate_bad_format EXIT nonzero STDERR "format"
                COMMAND generate --format xyz --out @TMP@/hip)
hipfai_cli_test(NAME generate_needs_out EXIT nonzero STDERR "out"
                COMMAND generate --ce-deg 20)
