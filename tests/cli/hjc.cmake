# hipfai hjc: the five HJC estimators on the real CT bones, and one-line errors on bad input.
set(HJC_LHDL "@SOURCE@/meshes/real-hips/LHDL_CT")
hipfai_cli_test(NAME hjc_real_bones_json EXIT 0
  COMMAND hjc --femur ${HJC_LHDL}/femur_r.ply --pelvis ${HJC_LHDL}/pelvis_no_sacrum.ply --json)
hipfai_cli_test(NAME hjc_real_bones_one_method EXIT 0
  COMMAND hjc --femur ${HJC_LHDL}/femur_r.ply --pelvis ${HJC_LHDL}/pelvis_no_sacrum.ply --method doublesphere)
hipfai_cli_test(NAME hjc_one_mesh EXIT nonzero STDERR "--pelvis is required"
  COMMAND hjc --femur ${HJC_LHDL}/femur_r.ply)
# A flat square: no femoral head.
set(hjc_square ${CMAKE_BINARY_DIR}/cli-tmp/hjc_square.obj)
file(WRITE ${hjc_square} "v 0 0 0\nv 40 0 0\nv 40 40 0\nv 0 40 0\nf 1 2 3\nf 1 3 4\n")
hipfai_cli_test(NAME hjc_no_head EXIT nonzero STDERR "^hipfai: error: .*hjc_square.obj: no femoral head found"
  COMMAND hjc --femur ${hjc_square} --pelvis ${HJC_LHDL}/pelvis_no_sacrum.ply)
# A given head region that is flat (the square's four vertices).
set(hjc_flat_region ${CMAKE_BINARY_DIR}/cli-tmp/hjc_flat_region.txt)
file(WRITE ${hjc_flat_region} "0 1 2 3\n")
hipfai_cli_test(NAME hjc_flat_region EXIT nonzero STDERR "femoral head region: the points are coplanar"
  COMMAND hjc --femur ${hjc_square} --pelvis ${HJC_LHDL}/pelvis_no_sacrum.ply
          --femoral-head-region ${hjc_flat_region})
hipfai_cli_test(NAME hjc_bad_region_file EXIT nonzero STDERR "is not a vertex index"
  COMMAND hjc --femur ${HJC_LHDL}/femur_r.ply --pelvis ${HJC_LHDL}/pelvis_no_sacrum.ply
          --femoral-head-region ${HJC_LHDL}/hip.json)
hipfai_cli_test(NAME study_hjc_bones_one_mesh EXIT nonzero STDERR "give both --femur and --pelvis"
  COMMAND study hjc --femur ${HJC_LHDL}/femur_r.ply --out @TMP@/out)
