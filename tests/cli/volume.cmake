# hipfai generate --volume: hexahedral soft-tissue meshes (volume.msh) next to the surfaces; bad
# volume options fail at parse time with one line.
hipfai_cli_test(NAME generate_volume EXIT 0
                COMMAND generate --ce-deg 20 --alpha-deg 40 --edge-mm 3 --volume --out @TMP@/hip)
hipfai_cli_test(NAME generate_volume_layers_zero EXIT nonzero STDERR "volume-layers"
                COMMAND generate --edge-mm 3 --volume --volume-layers 0 --out @TMP@/hip)
hipfai_cli_test(NAME generate_volume_edge_out_of_range EXIT nonzero STDERR "volume-edge-mm"
                COMMAND generate --edge-mm 3 --volume --volume-edge-mm 0.1 --out @TMP@/hip)
hipfai_cli_test(NAME generate_volume_options_need_volume EXIT nonzero STDERR "requires --volume"
                COMMAND generate --edge-mm 3 --volume-layers 3 --out @TMP@/hip)
