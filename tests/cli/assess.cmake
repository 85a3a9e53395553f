# hipfai assess: the patient-specific assessment on the real CT bones (frame found on them, a
# user motion, both resections), and one-line errors for meaningless input.
set(ASSESS_LHDL "@SOURCE@/meshes/real-hips/LHDL_CT")
hipfai_cli_test(NAME assess_real_bones EXIT 0
  COMMAND assess --femur ${ASSESS_LHDL}/femur_r.ply --pelvis ${ASSESS_LHDL}/pelvis_no_sacrum.ply --out @TMP@/out)
# An OpenSim motion (degrees): three steps of flexion with some adduction and internal rotation.
set(assess_mot ${CMAKE_BINARY_DIR}/cli-tmp/assess_flexion.mot)
file(WRITE ${assess_mot} "flexion\nversion=1\nnRows=3\nnColumns=4\ninDegrees=yes\nendheader\n"
     "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\n0\t0\t0\t0\n0.5\t45\t5\t5\n1\t90\t10\t10\n")
hipfai_cli_test(NAME assess_motion_and_resections EXIT 0
  COMMAND assess --femur ${ASSESS_LHDL}/femur_r.ply --pelvis ${ASSESS_LHDL}/pelvis_no_sacrum.ply
          --motion ${assess_mot} --resect-alpha-deg 45 --trim-rim-deg 5 --out @TMP@/out)
hipfai_cli_test(NAME assess_side_against_the_bones EXIT nonzero STDERR "lies in the right half of the pelvis"
  COMMAND assess --femur ${ASSESS_LHDL}/femur_r.ply --pelvis ${ASSESS_LHDL}/pelvis_no_sacrum.ply --side left
          --out @TMP@/out)
set(assess_square ${CMAKE_BINARY_DIR}/cli-tmp/assess_square.obj)
file(WRITE ${assess_square} "v 0 0 0\nv 40 0 0\nv 40 40 0\nv 0 40 0\nf 1 2 3\nf 1 3 4\n")
hipfai_cli_test(NAME assess_femur_without_head EXIT nonzero STDERR "no femoral head"
  COMMAND assess --femur ${assess_square} --pelvis ${ASSESS_LHDL}/pelvis_no_sacrum.ply --out @TMP@/out)
hipfai_cli_test(NAME assess_motion_not_a_motion EXIT nonzero STDERR "a motion is a .csv"
  COMMAND assess --femur ${ASSESS_LHDL}/femur_r.ply --pelvis ${ASSESS_LHDL}/pelvis_no_sacrum.ply
          --motion ${ASSESS_LHDL}/hip.json --out @TMP@/out)
set(assess_bad_mot ${CMAKE_BINARY_DIR}/cli-tmp/assess_bad.mot)
file(WRITE ${assess_bad_mot} "bad\nversion=1\nnRows=1\nnColumns=2\ninDegrees=yes\nendheader\ntime\tknee_angle_r\n0\t10\n")
hipfai_cli_test(NAME assess_motion_without_hip_columns EXIT nonzero STDERR "assess_bad.mot"
  COMMAND assess --femur ${ASSESS_LHDL}/femur_r.ply --pelvis ${ASSESS_LHDL}/pelvis_no_sacrum.ply
          --motion ${assess_bad_mot} --out @TMP@/out)
hipfai_cli_test(NAME study_assess_truth_quick EXIT 0 COMMAND study assess-truth --quick --out @TMP@/out)
# A scene can ask for the same (outputs: [assessment]): the plan has the stage, the run writes assessment/.
hipfai_cli_test(NAME run_assessment_scene EXIT 0
  COMMAND run @SOURCE@/meshes/scenes/assess_cam_hip.yaml --out @TMP@/out --cache @TMP@/cache)
add_test(NAME cli.run_plan_assessment_stage
         COMMAND sh -c "\"$1\" run \"$2\" --plan | grep -q '^[0-9]*[.] assessment: femur_bone and acetabular_bone'"
                 sh $<TARGET_FILE:hipfai> ${CMAKE_SOURCE_DIR}/meshes/scenes/assess_cam_hip.yaml)
set_tests_properties(cli.run_plan_assessment_stage PROPERTIES LABELS "cli;fast" TIMEOUT 60)
hipfai_cli_test(NAME study_soft_tissue_truth_quick EXIT 0
  COMMAND study soft-tissue-truth --quick --out @TMP@/out --cache @TMP@/cache)
# --soft-tissue: the same hip model folder as `hipfai soft-tissue` writes, from the assessment made.
set(assess_soft_tmp ${CMAKE_BINARY_DIR}/cli-tmp/assess_soft_tissue)
add_test(NAME cli.assess_soft_tissue
         COMMAND sh -c "set -e; rm -rf \"$2\"; mkdir -p \"$2\"; \
\"$1\" assess --femur \"$3/femur_r.ply\" --pelvis \"$3/pelvis_no_sacrum.ply\" --out \"$2/out\" --soft-tissue \"$2/st\" --quiet > \"$2/log\"; \
grep -q '\"soft_tissue\": \"synthesised\"' \"$2/st/model.json\" || { echo 'no synthesised model.json' >&2; exit 1; }; \
\"$1\" soft-tissue --femur \"$3/femur_r.ply\" --pelvis \"$3/pelvis_no_sacrum.ply\" --out \"$2/alone\" > /dev/null; \
for f in femoral_cartilage.ply acetabular_cartilage.ply labrum.ply model.json; do cmp \"$2/st/$f\" \"$2/alone/$f\"; done"
                 sh $<TARGET_FILE:hipfai> ${assess_soft_tmp} ${CMAKE_SOURCE_DIR}/meshes/real-hips/LHDL_CT)
set_tests_properties(cli.assess_soft_tissue PROPERTIES LABELS "cli;fast" TIMEOUT 120)
