hipfai_cli_test(NAME run_plan EXIT 0 COMMAND run @SOURCE@/meshes/scenes/normal_hip.yaml --plan)
hipfai_cli_test(NAME run_missing_scene EXIT nonzero COMMAND run @TMP@/none.yaml)
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/bad_scene.yaml "schema_version: 1\nunits: {length: m, angle: deg}\n")
hipfai_cli_test(NAME run_bad_units EXIT nonzero STDERR "bad_scene.yaml:2: units.length"
  COMMAND run ${CMAKE_BINARY_DIR}/cli-tmp/bad_scene.yaml --plan)
hipfai_cli_test(NAME study_fai_bad_edge EXIT nonzero STDERR "edge-mm" COMMAND study fai --edge-mm 0)
hipfai_cli_test(NAME study_fai_bad_radial_rule EXIT nonzero STDERR "radial-rule" COMMAND study fai --radial-rule adjacent)
hipfai_cli_test(NAME study_fai_bad_pose_sequence EXIT nonzero STDERR "pose-sequence" COMMAND study fai --pose-sequence zyx)
hipfai_cli_test(NAME study_fai_missing_hip_parameters EXIT nonzero STDERR "none.json: no such file"
  COMMAND study fai --hip-parameters @TMP@/none.json --out @TMP@/fai-none)
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/bad_hip_parameters.json "{\"acetabular_anteversion\": 14}")
hipfai_cli_test(NAME study_fai_unknown_hip_parameter EXIT nonzero STDERR "unknown parameter 'acetabular_anteversion'"
  COMMAND study fai --hip-parameters ${CMAKE_BINARY_DIR}/cli-tmp/bad_hip_parameters.json --out @TMP@/fai-bad)
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/range_hip_parameters.json "{\"acetabular_anteversion_deg\": 90}")
hipfai_cli_test(NAME study_fai_hip_parameter_out_of_range EXIT nonzero STDERR "acetabular_anteversion_deg = 90 is outside"
  COMMAND study fai --hip-parameters ${CMAKE_BINARY_DIR}/cli-tmp/range_hip_parameters.json --out @TMP@/fai-bad)
hipfai_cli_test(NAME study_fai_bad_curvilinear_samples EXIT nonzero STDERR "curvilinear-samples" COMMAND study fai --curvilinear-samples edges)
# The sensitivity study on one parameter (its two variants and the reference, both hips: 6 hips).
hipfai_cli_test(NAME study_sensitivity_one_parameter EXIT 0
  COMMAND study sensitivity --parameters cam_height_mm --sub-motions 6 --out @TMP@/sensitivity)
hipfai_cli_test(NAME study_sensitivity_unknown_parameter EXIT nonzero STDERR "no variants of parameter 'neck_girth'"
  COMMAND study sensitivity --parameters neck_girth --out @TMP@/sensitivity)
# The validation study and its report: bad options and a folder without results are one-line errors.
hipfai_cli_test(NAME study_validate_bad_level EXIT nonzero STDERR "fe-level" COMMAND study validate --fe-level medium)
hipfai_cli_test(NAME study_validate_too_few_steps EXIT nonzero STDERR "steps" COMMAND study validate --steps 2)
hipfai_cli_test(NAME report_correlation_no_results EXIT nonzero STDERR "steps.csv: cannot open"
  COMMAND report correlation @TMP@)
hipfai_cli_test(NAME study_fai_bad_femoral_neutral EXIT nonzero STDERR "femoral-neutral"
  COMMAND study fai --femoral-neutral knee)
