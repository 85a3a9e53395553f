set(LHDL "@SOURCE@/meshes/real-hips/LHDL_CT")
hipfai_cli_test(NAME collide_cylindrical_real_bones EXIT 0
  COMMAND collide --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm 143.80,243.46,-432.58 --axis 1,0,0 --angle-deg 30 --method cylindrical
          --out @TMP@/pairs.csv --vtp @TMP@/femur_depth.vtp)
hipfai_cli_test(NAME collide_radial_real_bones EXIT 0
  COMMAND collide --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm 143.80,243.46,-432.58 --axis 1,0,0 --angle-deg 30 --method radial
          --mapping spherical --fixed-inside-mobile --out @TMP@/pairs.csv)
hipfai_cli_test(NAME collide_missing_mesh EXIT nonzero STDERR "does not exist"
  COMMAND collide --fixed @TMP@/nowhere.ply --mobile ${LHDL}/femur_r.ply --center-mm 0,0,0)
hipfai_cli_test(NAME collide_zero_axis EXIT nonzero STDERR "zero length"
  COMMAND collide --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm 0,0,0 --axis 0,0,0 --method cylindrical)
hipfai_cli_test(NAME collide_nan_centre EXIT nonzero STDERR "center-mm"
  COMMAND collide --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm nan,0,0)
hipfai_cli_test(NAME collide_bad_method EXIT nonzero STDERR "method"
  COMMAND collide --fixed ${LHDL}/pelvis_no_sacrum.ply --mobile ${LHDL}/femur_r.ply
          --center-mm 0,0,0 --method bvh)
# Overlap already at angle 0 (meshes written by rom.cmake): a warning, the depths still reported.
set(OVERLAP_DIR ${CMAKE_BINARY_DIR}/cli-tmp/rom_start_overlap_meshes)
hipfai_cli_test(NAME collide_start_overlap_warns EXIT 0
  STDERR "^hipfai: warning: the bodies already intersect in the start pose \\(angle 0\\): 4 mobile vertices"
  COMMAND collide --fixed ${OVERLAP_DIR}/fixed_box.obj --mobile ${OVERLAP_DIR}/mobile_box.obj
          --center-mm 5,5,5 --axis 0,0,1 --angle-deg 0 --method cylindrical)
