# hipfai bench collision: a --quick run writes the report, CSV and plots; bad options fail with one line.
hipfai_cli_test(NAME bench_collision_quick EXIT 0
                COMMAND bench collision --quick --out @TMP@/bench)
hipfai_cli_test(NAME bench_collision_bad_threads EXIT nonzero STDERR "threads"
                COMMAND bench collision --quick --threads 9 --out @TMP@/bench)
