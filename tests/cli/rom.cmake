# hipfai rom: exact range of motion of the real CT femur against the pelvis about the HJC.
set(LHDL "@SOURCE@/meshes/real-hips/LHDL_CT")
set(HJC "143.80,243.46,-432.58")
hipfai_cli_test(NAME rom_real_bones EXIT 0
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm ${HJC} --axis 0,0,1 --csv @TMP@/rom.csv)
hipfai_cli_test(NAME rom_real_bones_fan EXIT 0
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm ${HJC} --fan-plane-normal 0,1,0 --fan-steps 3 --csv @TMP@/fan.csv)
hipfai_cli_test(NAME rom_missing_mesh EXIT nonzero STDERR "nowhere\\.ply"
  COMMAND rom --fixed @TMP@/nowhere.ply --mobile ${LHDL}/femur_r.ply --center-mm 0,0,0 --axis 0,0,1)
hipfai_cli_test(NAME rom_zero_axis EXIT nonzero STDERR "^hipfai: error: --axis: the axis has zero length$"
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm 0,0,0 --axis 0,0,0)
hipfai_cli_test(NAME rom_no_axis EXIT nonzero STDERR "error: --axis: required unless"
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply --center-mm 0,0,0)
hipfai_cli_test(NAME rom_axis_and_fan EXIT nonzero STDERR "excludes"
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply --center-mm 0,0,0
          --axis 0,0,1 --fan-plane-normal 0,1,0)
hipfai_cli_test(NAME rom_bad_fan_steps EXIT nonzero STDERR "fan-steps"
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply --center-mm 0,0,0
          --fan-plane-normal 0,1,0 --fan-steps 0)
hipfai_cli_test(NAME rom_nan_centre EXIT nonzero STDERR "center-mm"
  COMMAND rom --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply --center-mm nan,0,0 --axis 0,0,1)
