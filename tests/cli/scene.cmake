# Scenes with FE outputs: `hipfai run --plan` shows the FE stage with its level, the fe block is
# validated before any work, and a small FE scene runs end to end.
set(scene_tmp ${CMAKE_BINARY_DIR}/cli-tmp/scene_fe)
file(MAKE_DIRECTORY ${scene_tmp})

add_test(NAME cli.run_plan_fe_stage
         COMMAND sh -c "out=$(\"$1\" run \"$2\" --plan) || exit 1; echo \"$out\"; \
echo \"$out\" | grep -q 'finite-element: contact FE over the motion (level coarse; sitting-down load, body weight 700 N)  (x4 steps)' \
|| { echo 'no FE stage in the plan' >&2; exit 1; }"
                 sh $<TARGET_FILE:hipfai> ${CMAKE_SOURCE_DIR}/meshes/scenes/fe_pincer.yaml)
set_tests_properties(cli.run_plan_fe_stage PROPERTIES LABELS "cli;fast" TIMEOUT 60)

# A penetration-only scene plans no FE.
add_test(NAME cli.run_plan_no_fe_stage
         COMMAND sh -c "out=$(\"$1\" run \"$2\" --plan) || exit 1; echo \"$out\"; \
! echo \"$out\" | grep -q 'finite-element'"
                 sh $<TARGET_FILE:hipfai> ${CMAKE_SOURCE_DIR}/meshes/scenes/cam_radial_only.yaml)
set_tests_properties(cli.run_plan_no_fe_stage PROPERTIES LABELS "cli;fast" TIMEOUT 60)

file(WRITE ${scene_tmp}/bad_fe_level.yaml
  "schema_version: 1\nunits: {length: mm, angle: deg}\nhip:\n  parametric: {ce_deg: 40, alpha_deg: 40}\n"
  "motion: {builtin: standing_to_sitting, sub_motions: 2}\noutputs: [von_mises]\nfe: {level: medium}\n")
hipfai_cli_test(NAME run_fe_bad_level EXIT nonzero STDERR "bad_fe_level.yaml:7: fe.level: unknown level 'medium'"
  COMMAND run ${scene_tmp}/bad_fe_level.yaml --plan)

if(TARGET hipfai_fem)
  # FE outputs only, standing to sitting in 2 steps at the coarse level on a 3 mm hip (~10 s):
  # steps.csv gets the FE columns, no penetration column.
  file(WRITE ${scene_tmp}/fe_only.yaml
    "schema_version: 1\nunits: {length: mm, angle: deg}\nname: fe-only\nhip:\n"
    "  parametric: {ce_deg: 40, alpha_deg: 40, edge_mm: 3.0}\n"
    "motion: {builtin: standing_to_sitting, sub_motions: 2}\noutputs: [von_mises, contact_pressure]\n"
    "fe: {level: coarse}\n")
  add_test(NAME cli.run_fe_scene
           COMMAND sh -c "rm -rf \"$2/out\" \"$2/cache\" && out=$(\"$1\" run \"$2/fe_only.yaml\" --out \"$2/out\" --cache \"$2/cache\" 2>/dev/null) \
|| exit 1; echo \"$out\"; echo \"$out\" | grep -q 'FE level coarse' || { echo 'no FE summary' >&2; exit 1; }; \
head -1 \"$2/out/steps.csv\" | grep -q 'fe_status,von_mises_max_femoral_cartilage_mpa,' || { echo 'no FE columns' >&2; exit 1; }; \
! head -1 \"$2/out/steps.csv\" | grep -q 'max_radial_mm'"
                   sh $<TARGET_FILE:hipfai> ${scene_tmp})
  set_tests_properties(cli.run_fe_scene PROPERTIES LABELS "cli;fem;slow" TIMEOUT 300)
endif()

# A scene on a hip model folder, run from an empty working directory: the cache folder
# (penetration tables and pose caches) is made where it is needed.
set(scene_empty_tmp ${CMAKE_BINARY_DIR}/cli-tmp/scene_empty_dir)
add_test(NAME cli.run_model_dir_scene_from_an_empty_folder
         COMMAND sh -c "rm -rf \"$2\" && mkdir -p \"$2/work\" && \
\"$1\" generate --ce-deg 30 --alpha-deg 70 --edge-mm 3 --out \"$2/hip\" >/dev/null && \
printf 'schema_version: 1\\nunits: {length: mm, angle: deg}\\nname: from-empty\\nhip:\\n  model_dir: %s\\nmotion: {builtin: standing_to_sitting, sub_motions: 3}\\noutputs: [curvilinear_depth, radial_depth]\\n' \"$2/hip\" > \"$2/scene.yaml\" && \
cd \"$2/work\" && \"$1\" run \"$2/scene.yaml\" && test -d \"$2/work/cache\" && ls \"$2/work/cache\" | grep -q 'cylindrical-pose-cache-' \
|| { echo 'no pose cache in the new cache folder' >&2; exit 1; }"
                 sh $<TARGET_FILE:hipfai> ${scene_empty_tmp})
set_tests_properties(cli.run_model_dir_scene_from_an_empty_folder PROPERTIES LABELS "cli;fast" TIMEOUT 120)

# Every example scene (meshes/scenes: penetration on a generated hip, radial only, FE outputs, the
# assessment) runs from an empty working folder with the default output and cache folders, and
# writes its results there.
set(scene_examples_tmp ${CMAKE_BINARY_DIR}/cli-tmp/example_scenes_from_an_empty_folder)
add_test(NAME cli.example_scenes_from_an_empty_folder
         COMMAND sh -c "set -e; for scene in \"$2\"/*.yaml; do \
name=$(basename \"$scene\" .yaml); rm -rf \"$3/$name\"; mkdir -p \"$3/$name\"; cd \"$3/$name\"; \
\"$1\" run \"$scene\" > run.log 2>&1 || { echo \"$name failed:\" >&2; tail -5 run.log >&2; exit 1; }; \
ls -R . | grep -q 'results.h5\\|assessment.json' || { echo \"$name: no results in its folder\" >&2; exit 1; }; \
done"
                 sh $<TARGET_FILE:hipfai> ${CMAKE_SOURCE_DIR}/meshes/scenes ${scene_examples_tmp})
set_tests_properties(cli.example_scenes_from_an_empty_folder PROPERTIES LABELS "cli;slow" TIMEOUT 600)

# A scene on segmented bones (hip.bones): dressed with synthesised soft tissue into the cache, the
# depths computed, and the second run takes the dressed folder from the cache.
set(scene_bones_tmp ${CMAKE_BINARY_DIR}/cli-tmp/scene_on_bones)
add_test(NAME cli.scene_on_bones
         COMMAND sh -c "set -e; rm -rf \"$2\"; mkdir -p \"$2\"; cd \"$2\"; \
printf 'schema_version: 1\\nunits: {length: mm, angle: deg}\\nname: bones\\nhip:\\n  bones: {femur: %s/femur_r.ply, pelvis: %s/pelvis_no_sacrum.ply}\\nmotion: {medical: flexion, max_deg: 120, steps: 6}\\noutputs: [curvilinear_depth, radial_depth]\\n' \"$3\" \"$3\" > scene.yaml; \
\"$1\" run scene.yaml > first.log; grep -q 'dress-bones x1' first.log || { cat first.log; exit 1; }; \
\"$1\" run scene.yaml > second.log; grep -q 'from cache: dress-bones x1' second.log || { cat second.log; exit 1; }; \
ls cache | grep -q '^dressed-femur_r-'"
                 sh $<TARGET_FILE:hipfai> ${scene_bones_tmp} ${CMAKE_SOURCE_DIR}/meshes/real-hips/LHDL_CT)
set_tests_properties(cli.scene_on_bones PROPERTIES LABELS "cli;fast" TIMEOUT 120)
