# hipfai mesh-info: the real CT femur reads and reports; bad files fail with one line naming them.
set(real_femur @SOURCE@/meshes/real-hips/LHDL_CT/femur_r.ply)
hipfai_cli_test(NAME mesh_info_real_femur EXIT 0 COMMAND mesh-info ${real_femur})
hipfai_cli_test(NAME mesh_info_real_femur_json EXIT 0 COMMAND mesh-info --json ${real_femur})
hipfai_cli_test(NAME mesh_info_missing_file EXIT nonzero STDERR "^hipfai: error: .*absent\\.stl"
                COMMAND mesh-info @TMP@/absent.stl)

# Corrupt inputs, written at configure time into the test's scratch folder (@TMP@).
hipfai_cli_test(NAME mesh_info_corrupt_ply EXIT nonzero
                STDERR "^hipfai: error: .*corrupt\\.ply: PLY vertex element lacks an x, y or z property$"
                COMMAND mesh-info @TMP@/corrupt.ply)
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/mesh_info_corrupt_ply/corrupt.ply
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n1\n2\n")

hipfai_cli_test(NAME mesh_info_corrupt_stl EXIT nonzero
                STDERR "^hipfai: error: .*corrupt\\.stl: line 4: bad number 'zero'$"
                COMMAND mesh-info @TMP@/corrupt.stl)
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/mesh_info_corrupt_stl/corrupt.stl
     "solid broken\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n")

hipfai_cli_test(NAME mesh_info_unknown_format EXIT nonzero STDERR "unknown mesh format '\\.off'"
                COMMAND mesh-info @TMP@/mesh.off)
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/mesh_info_unknown_format/mesh.off "OFF\n3 1 0\n")
