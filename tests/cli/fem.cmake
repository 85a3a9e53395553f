# FE contact model: verification cases from the command line, and 1 vs 2 MPI ranks.
if(TARGET hipfai_fem)
  hipfai_cli_test(NAME fem_verify_uniaxial EXIT 0
                  COMMAND fem verify --case uniaxial_layer --case uniaxial_load_control
                          --csv @TMP@/uniaxial.csv)
  hipfai_cli_test(NAME fem_verify_unknown_case EXIT nonzero STDERR "no_such_case not in"
                  COMMAND fem verify --case no_such_case)
  hipfai_cli_test(NAME fem_verify_bad_csv EXIT nonzero STDERR "no-such-dir/x.csv"
                  COMMAND fem verify --case uniaxial_layer --csv @TMP@/no-such-dir/x.csv)

  # Same case on 1 and 2 ranks: every computed value must agree to 1e-9 relative (the CG
  # tolerance is 1e-12 relative residual; the partitioning changes only round-off and the AMG).
  find_program(HIPFAI_MPIRUN mpirun)
  if(HIPFAI_MPIRUN)
    set(fem_mpi_tmp ${CMAKE_BINARY_DIR}/cli-tmp/fem_mpi_ranks)
    file(MAKE_DIRECTORY ${fem_mpi_tmp})
    foreach(case uniaxial_layer stacked_layers)
      add_test(NAME cli.fem_mpi_1_vs_2_ranks_${case}
               COMMAND sh -c "\"$1\" fem verify --case ${case} --csv \"$2/${case}_1.csv\" >/dev/null && \
\"$3\" --allow-run-as-root --oversubscribe -np 2 \"$1\" fem verify --case ${case} --csv \"$2/${case}_2.csv\" >/dev/null && \
awk -F, 'NR==FNR { if (FNR > 1) v[FNR] = $4; next } FNR > 1 { d = $4 - v[FNR]; if (d < 0) d = -d; \
s = v[FNR] < 0 ? -v[FNR] : v[FNR]; if (d > 1e-9 * s) { print \"rank mismatch: \" $2 \": \" v[FNR] \" vs \" $4 > \"/dev/stderr\"; bad = 1 } \
if ($12 != 2) { print \"expected 2 ranks, got \" $12 > \"/dev/stderr\"; bad = 1 } } END { exit bad }' \
\"$2/${case}_1.csv\" \"$2/${case}_2.csv\""
                       sh $<TARGET_FILE:hipfai> ${fem_mpi_tmp} ${HIPFAI_MPIRUN})
      set_tests_properties(cli.fem_mpi_1_vs_2_ranks_${case} PROPERTIES LABELS "cli;fem;slow" TIMEOUT 300)
    endforeach()
    # The hip model (direct solver on the reduced system, load control, four contact pairs) on 1
    # and 2 ranks, a generated CE 20 / alpha 40 hip at the coarse level, standing-to-sitting in 2
    # steps: pressures, area, translation and von Mises agree to 1e-8 relative (round-off of
    # MUMPS on a different partition; the residual penetration, ~1e-16 mm, is not compared).
    add_test(NAME cli.fem_mpi_1_vs_2_ranks_hip
             COMMAND sh -c "\"$1\" generate --ce-deg 20 --alpha-deg 40 --edge-mm 3 --out \"$2/hip\" >/dev/null && \
\"$1\" fem run --model \"$2/hip\" --steps 2 --out \"$2/hip_1.h5\" --csv \"$2/hip_1.csv\" >/dev/null && \
\"$3\" --allow-run-as-root --oversubscribe -np 2 \"$1\" fem run --model \"$2/hip\" --steps 2 --out \"$2/hip_2.h5\" --csv \"$2/hip_2.csv\" >/dev/null && \
awk -F, 'NR==FNR { for (c = 1; c <= NF; ++c) v[FNR, c] = $c; next } FNR > 1 { \
if ($3 != 2) { print \"expected 2 ranks, got \" $3 > \"/dev/stderr\"; bad = 1 } \
split(\"6 7 8 10 11 12 13 14 15\", cols, \" \"); for (k in cols) { c = cols[k]; d = $c - v[FNR, c]; if (d < 0) d = -d; \
s = v[FNR, c] < 0 ? -v[FNR, c] : v[FNR, c]; if (d > 1e-8 * s + 1e-14) { print \"rank mismatch, step \" $1 \", column \" c \": \" v[FNR, c] \" vs \" $c > \"/dev/stderr\"; bad = 1 } } } \
END { if (FNR < 3) { print \"too few rows\" > \"/dev/stderr\"; bad = 1 } exit bad }' \"$2/hip_1.csv\" \"$2/hip_2.csv\""
                     sh $<TARGET_FILE:hipfai> ${fem_mpi_tmp} ${HIPFAI_MPIRUN})
    set_tests_properties(cli.fem_mpi_1_vs_2_ranks_hip PROPERTIES LABELS "cli;fem;slow" TIMEOUT 600)
  endif()
endif()

# Motion on concentric shells: option errors are one stderr line, before any solve.
if(TARGET hipfai_fem)
  hipfai_cli_test(NAME fem_shells_bad_out EXIT nonzero STDERR "no-such-dir/r.h5"
                  COMMAND fem shells --steps 1 --out @TMP@/no-such-dir/r.h5)
  hipfai_cli_test(NAME fem_shells_missing_motion EXIT nonzero STDERR "no-such.csv"
                  COMMAND fem shells --motion @TMP@/no-such.csv --out @TMP@/r.h5)
endif()

# Hip model: a bad --model fails with one line before any solve.
if(TARGET hipfai_fem)
  hipfai_cli_test(NAME fem_run_missing_model_dir EXIT nonzero STDERR "no-such-model"
                  COMMAND fem run --model @TMP@/no-such-model --out @TMP@/r.h5)
  # An existing directory without model.json: the loader's error names the file.
  hipfai_cli_test(NAME fem_run_model_without_json EXIT nonzero STDERR "model.json"
                  COMMAND fem run --model @TMP@ --steps 1 --out @TMP@/r.h5)
  hipfai_cli_test(NAME fem_run_bad_level EXIT nonzero STDERR "level"
                  COMMAND fem run --model @TMP@ --level medium --out @TMP@/r.h5)
  # --vtu-prefix: a missing folder is made; one that cannot be (a file in its path) is a one-line
  # error before the solve, not deal.II's internal error after the last step.
  set(fem_vtu_tmp ${CMAKE_BINARY_DIR}/cli-tmp/fem_run_vtu_prefix)
  file(MAKE_DIRECTORY ${fem_vtu_tmp})
  add_test(NAME cli.fem_run_vtu_prefix_folders
           COMMAND sh -c "rm -rf \"$2/new\" \"$2/bad.h5\" \"$2/ok.h5\" && \"$1\" generate --ce-deg 20 --alpha-deg 40 --edge-mm 5 --out \"$2/hip\" >/dev/null && \
: > \"$2/a-file\" && ! \"$1\" fem run --model \"$2/hip\" --level coarse --steps 1 --out \"$2/bad.h5\" \
--vtu-prefix \"$2/a-file/sub/f\" --vtu-every 1 >/dev/null 2>\"$2/err.txt\" && \
grep -q 'a-file/sub/f: cannot write the VTU files there (--vtu-prefix)' \"$2/err.txt\" && \
test \"$(wc -l < \"$2/err.txt\")\" -eq 1 && ! test -e \"$2/bad.h5\" && \
\"$1\" fem run --model \"$2/hip\" --level coarse --steps 1 --out \"$2/ok.h5\" \
--vtu-prefix \"$2/new/dir/f\" --vtu-every 1 >/dev/null && test -s \"$2/new/dir/f_1.vtu\""
           sh $<TARGET_FILE:hipfai> ${fem_vtu_tmp})
  set_tests_properties(cli.fem_run_vtu_prefix_folders PROPERTIES LABELS "cli;fem" TIMEOUT 300)
  # fem levels: option errors before any solve, and no report left behind.
  hipfai_cli_test(NAME fem_levels_one_level EXIT nonzero STDERR "at least two levels"
                  COMMAND fem levels --model @TMP@ --levels coarse --out @TMP@/levels)
  hipfai_cli_test(NAME fem_levels_bad_level EXIT nonzero STDERR "medium"
                  COMMAND fem levels --model @TMP@ --levels coarse,medium --out @TMP@/levels)
  hipfai_cli_test(NAME fem_levels_bad_solver EXIT nonzero STDERR "--solver"
                  COMMAND fem levels --model @TMP@ --solver gauss --out @TMP@/levels)
  hipfai_cli_test(NAME fem_levels_model_without_json EXIT nonzero STDERR "model.json"
                  COMMAND fem levels --model @TMP@ --levels coarse,default --steps 1 --out @TMP@/levels)
endif()

# --peak-radius-mm (ball-averaged peaks, fem/peak_measures.h): finite and > 0, checked when the
# options are parsed, before the model is read.
if(TARGET hipfai_fem)
  foreach(radius 0 -1 inf nan abc)
    hipfai_cli_test(NAME fem_run_bad_peak_radius_${radius} EXIT nonzero STDERR "peak-radius-mm"
                    COMMAND fem run --model @TMP@ --peak-radius-mm ${radius} --out @TMP@/r.h5)
    hipfai_cli_test(NAME fem_levels_bad_peak_radius_${radius} EXIT nonzero STDERR "peak-radius-mm"
                    COMMAND fem levels --model @TMP@ --peak-radius-mm ${radius} --out @TMP@/levels)
  endforeach()
endif()

# --labrum-refinement (the labrum meshed N times finer): an integer 1-4.
if(TARGET hipfai_fem)
  foreach(factor 0 5 1.5 abc)
    hipfai_cli_test(NAME fem_run_bad_labrum_refinement_${factor} EXIT nonzero STDERR "labrum-refinement"
                    COMMAND fem run --model @TMP@ --labrum-refinement ${factor} --out @TMP@/r.h5)
    hipfai_cli_test(NAME fem_levels_bad_labrum_refinement_${factor} EXIT nonzero STDERR "labrum-refinement"
                    COMMAND fem levels --model @TMP@ --labrum-refinement ${factor} --out @TMP@/levels)
  endforeach()
endif()

# scripts/fem-sweep: a model whose run fails is listed in summary.csv with its exit status, and
# the sweep exits 1 so that whoever ran it notices (it used to exit 0 however many failed).
if(TARGET hipfai_fem)
  set(fem_sweep_tmp ${CMAKE_BINARY_DIR}/cli-tmp/fem_sweep_failed_model)
  add_test(NAME cli.fem_sweep_failed_model_exits_1
           COMMAND sh -c "rm -rf \"$2\" && mkdir -p \"$2/grid/broken\" && echo '{}' > \"$2/grid/broken/model.json\" && \
HIPFAI_BIN=\"$1\" \"$3/scripts/fem-sweep\" --grid \"$2/grid\" --out \"$2/out\" > \"$2/sweep.log\" 2>&1; status=$?; \
if [ $status -ne 1 ]; then echo \"fem-sweep exited $status, expected 1\"; cat \"$2/sweep.log\"; exit 1; fi; \
grep -Eq '^broken,[1-9][0-9]*,0,0,' \"$2/out/summary.csv\" || { echo 'summary.csv lacks the failed model'; cat \"$2/out/summary.csv\"; exit 1; }"
                   sh $<TARGET_FILE:hipfai> ${fem_sweep_tmp} ${CMAKE_SOURCE_DIR})
  set_tests_properties(cli.fem_sweep_failed_model_exits_1 PROPERTIES LABELS "cli;fast" TIMEOUT 120)
endif()
