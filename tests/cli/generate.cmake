# hipfai generate: one coarse hip with figures; bad options fail at parse time with one line.
hipfai_cli_test(NAME generate_one EXIT 0
                COMMAND generate --ce-deg 30 --alpha-deg 60 --edge-mm 5 --figures --out @TMP@/hip)
hipfai_cli_test(NAME generate_ce_out_of_range EXIT nonzero STDERR "ce-deg"
                COMMAND generate --ce-deg 60 --out @TMP@/hip)
hipfai_cli_test(NAME generate_bad_format EXIT nonzero STDERR "format"
                COMMAND generate --format xyz --out @TMP@/hip)
hipfai_cli_test(NAME generate_needs_out EXIT nonzero STDERR "out"
                COMMAND generate --ce-deg 20)
# A hip whose surfaces crashed Debian's gmsh 4.8 mesher while the cam was fused from three solids (a
# double free after "Impossible to mesh periodic surface" at CCD 136, CE 0 / alpha 80) generates since
# the cam is sewn from faces on shared curves (docs/generator-sweep.md). The crash handling itself,
# each meshing algorithm in a child process whose death is reported while this one goes on, is
# tested in tests/core/child_process_test.cpp; no input that still crashes gmsh is known.
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/ccd136_hip_parameters.json "{\"neck_shaft_angle_deg\": 136}\n")
hipfai_cli_test(NAME generate_ccd136_hip_that_crashed_gmsh EXIT 0
                COMMAND generate --ce-deg 0 --alpha-deg 80 --edge-mm 3
                        --hip-parameters ${CMAKE_BINARY_DIR}/cli-tmp/ccd136_hip_parameters.json --out @TMP@/hip)
hipfai_cli_test(NAME generate_missing_hip_parameters EXIT nonzero STDERR "none.json: no such file"
                COMMAND generate --ce-deg 20 --hip-parameters @TMP@/none.json --out @TMP@/hip)
