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

# Bodies that already intersect in the start pose: the box [9, 12] x [3, 5] x [4, 6]
# pokes 1 mm into the box [0, 10]^3 (4 corners inside, 1 mm deep). rom refuses with one line;
# --allow-start-overlap warns and reports the ranges; collide only warns.
function(hipfai_write_box_obj path min_x min_y min_z max_x max_y max_z)
  set(text "")
  foreach(i RANGE 7)
    math(EXPR bx "${i} & 1")
    math(EXPR by "(${i} >> 1) & 1")
    math(EXPR bz "(${i} >> 2) & 1")
    set(x ${min_x})
    set(y ${min_y})
    set(z ${min_z})
    if(bx)
      set(x ${max_x})
    endif()
    if(by)
      set(y ${max_y})
    endif()
    if(bz)
      set(z ${max_z})
    endif()
    string(APPEND text "v ${x} ${y} ${z}\n")
  endforeach()
  # Outward (counter-clockwise seen from outside) quads of the corners above, 1-based, two triangles each.
  foreach(quad "1 3 4 2" "5 6 8 7" "1 2 6 5" "3 7 8 4" "1 5 7 3" "2 4 8 6")
    separate_arguments(q UNIX_COMMAND "${quad}")
    list(GET q 0 a)
    list(GET q 1 b)
    list(GET q 2 c)
    list(GET q 3 d)
    string(APPEND text "f ${a} ${b} ${c}\nf ${a} ${c} ${d}\n")
  endforeach()
  file(WRITE ${path} "${text}")
endfunction()
set(OVERLAP_DIR ${CMAKE_BINARY_DIR}/cli-tmp/rom_start_overlap_meshes)
hipfai_write_box_obj(${OVERLAP_DIR}/fixed_box.obj 0 0 0 10 10 10)
hipfai_write_box_obj(${OVERLAP_DIR}/mobile_box.obj 9 3 4 12 5 6)
hipfai_cli_test(NAME rom_start_overlap EXIT nonzero
  STDERR "^hipfai: error: the bodies already intersect in the start pose: 4 mobile vertices inside the fixed mesh \\(deepest 1 mm\\), .*use --allow-start-overlap"
  COMMAND rom --fixed ${OVERLAP_DIR}/fixed_box.obj --mobile ${OVERLAP_DIR}/mobile_box.obj
          --center-mm 5,5,5 --axis 0,0,1)
hipfai_cli_test(NAME rom_start_overlap_allowed EXIT 0
  STDERR "^hipfai: warning: the bodies already intersect in the start pose: 4 mobile vertices"
  COMMAND rom --fixed ${OVERLAP_DIR}/fixed_box.obj --mobile ${OVERLAP_DIR}/mobile_box.obj
          --center-mm 5,5,5 --axis 0,0,1 --allow-start-overlap)
hipfai_cli_test(NAME rom_start_overlap_touching EXIT 0
  COMMAND rom --fixed ${OVERLAP_DIR}/fixed_box.obj --mobile ${OVERLAP_DIR}/mobile_box.obj
          --center-mm 5,5,5 --axis 0,0,1 --touching-mm 1.5)
