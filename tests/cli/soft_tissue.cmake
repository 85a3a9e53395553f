# hipfai soft-tissue: cartilage and labrum synthesised on the real CT bones into a hip model folder
# (read back by `hipfai run`), and one-line errors for bones without a head or an acetabulum.
set(SOFT_LHDL "@SOURCE@/meshes/real-hips/LHDL_CT")
hipfai_cli_test(NAME soft_tissue_real_bones EXIT 0
  COMMAND soft-tissue --femur ${SOFT_LHDL}/femur_r.ply --pelvis ${SOFT_LHDL}/pelvis_no_sacrum.ply --out @TMP@/out)
set(soft_square ${CMAKE_BINARY_DIR}/cli-tmp/soft_tissue_square.obj)
file(WRITE ${soft_square} "v 0 0 0\nv 40 0 0\nv 40 40 0\nv 0 40 0\nf 1 2 3\nf 1 3 4\n")
hipfai_cli_test(NAME soft_tissue_femur_without_head EXIT nonzero STDERR "soft_tissue_square.obj: no femoral head"
  COMMAND soft-tissue --femur ${soft_square} --pelvis ${SOFT_LHDL}/pelvis_no_sacrum.ply --out @TMP@/out)
# A pelvis far from the head (its frame given, so it need not be whole) has no acetabulum there.
set(soft_frame ${CMAKE_BINARY_DIR}/cli-tmp/soft_tissue_frame.json)
file(WRITE ${soft_frame} "{\"side\": \"right\", \"frames\": {\"pelvis\": {\"origin_mm\": [0, 0, 0], \"right\": [1, 0, 0], "
                         "\"anterior\": [0, 1, 0], \"superior\": [0, 0, 1]}}}\n")
hipfai_cli_test(NAME soft_tissue_pelvis_without_acetabulum EXIT nonzero STDERR "soft_tissue_square.obj: no lunate surface"
  COMMAND soft-tissue --femur ${SOFT_LHDL}/femur_r.ply --pelvis ${soft_square} --frame ${soft_frame} --out @TMP@/out)
hipfai_cli_test(NAME soft_tissue_side_against_the_bones EXIT nonzero STDERR "lies in the right half of the pelvis"
  COMMAND soft-tissue --femur ${SOFT_LHDL}/femur_r.ply --pelvis ${SOFT_LHDL}/pelvis_no_sacrum.ply --side left
          --out @TMP@/out)
# The folder is a hip model `hipfai run` reads: a scene with the bone-to-bone depths over a motion.
set(soft_scene ${CMAKE_BINARY_DIR}/cli-tmp/soft_tissue_scene.yaml)
file(WRITE ${soft_scene} "schema_version: 1\nunits: {length: mm, angle: deg}\nname: soft-tissue-lhdl\n"
                         "hip: {model_dir: ${CMAKE_BINARY_DIR}/cli-tmp/soft_tissue_real_bones/out}\n"
                         "motion: {builtin: standing_to_sitting, sub_motions: 4}\n"
                         "outputs: [curvilinear_depth, radial_depth]\n")
hipfai_cli_test(NAME soft_tissue_model_runs EXIT 0 COMMAND run ${soft_scene} --out @TMP@/out --cache @TMP@/cache)
set_tests_properties(cli.soft_tissue_model_runs PROPERTIES DEPENDS cli.soft_tissue_real_bones)
# ... and what `fem run` solves: the synthesised layers meshed with hexahedra (coarse, 3 steps, all
# converged or the command fails).
if(HIPFAI_WITH_FEM)
  hipfai_cli_test(NAME soft_tissue_model_fem_run EXIT 0
    COMMAND fem run --model ${CMAKE_BINARY_DIR}/cli-tmp/soft_tissue_real_bones/out --level coarse --steps 3
            --out @TMP@/fe.h5 --csv @TMP@/fe.csv)
  set_tests_properties(cli.soft_tissue_model_fem_run PROPERTIES DEPENDS cli.soft_tissue_real_bones)
endif()
