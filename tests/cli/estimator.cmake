# estimator train / predict / validate: bad input is a one-line error and no model file.
file(WRITE ${CMAKE_BINARY_DIR}/cli-tmp/garbage_model.h5 "not an HDF5 file\n")
hipfai_cli_test(NAME estimator_predict_garbage_model EXIT nonzero STDERR "not a hipfai estimator model"
  COMMAND estimator predict --model ${CMAKE_BINARY_DIR}/cli-tmp/garbage_model.h5 --hip @TMP@)
hipfai_cli_test(NAME estimator_predict_missing_model EXIT nonzero STDERR "no such model file"
  COMMAND estimator predict --model @TMP@/none.h5 --hip @TMP@)
hipfai_cli_test(NAME estimator_train_no_fe EXIT nonzero STDERR "no FE results"
  COMMAND estimator train --out @TMP@/model.h5)
hipfai_cli_test(NAME estimator_train_missing_fe EXIT nonzero STDERR "cannot read the FE table"
  COMMAND estimator train --fe @TMP@/none --hips @TMP@ --out @TMP@/model.h5)
hipfai_cli_test(NAME estimator_validate_no_inputs EXIT nonzero STDERR "--fe and --hips are required"
  COMMAND estimator validate --out @TMP@/out)
hipfai_cli_test(NAME estimator_predict_bad_method EXIT nonzero STDERR "method"
  COMMAND estimator predict --model @TMP@/none.h5 --hip @TMP@ --method svm)

# --quick from nothing (its own cache): 5 generated hips, their FE (coarse, 6 steps), leave-one-out;
# the files other tools read have their columns; a prediction with the run's model has its
# columns; a second run from the cache writes the same leave-one-out table.
if(HIPFAI_WITH_FEM)
  set(estimator_tmp ${CMAKE_BINARY_DIR}/cli-tmp/estimator_validate_quick)
  file(MAKE_DIRECTORY ${estimator_tmp})
  add_test(NAME cli.estimator_validate_quick
           COMMAND sh -c "set -e; rm -rf \"$2/a\" \"$2/b\" \"$2/cache\"; \
\"$1\" estimator validate --quick --out \"$2/a\" --cache \"$2/cache\" > \"$2/a.log\" 2>&1 || { tail -5 \"$2/a.log\"; exit 1; }; \
head -1 \"$2/a/loo.csv\" | grep -qx 'hip,case,e_prime,method,mean_abs_error_percent,bordering,impinging' || { echo 'loo.csv columns' >&2; exit 1; }; \
head -1 \"$2/a/estimates.csv\" | grep -qx 'hip,case,e_prime,method,step,estimate,fe,error_percent' || { echo 'estimates.csv columns' >&2; exit 1; }; \
for m in pca_nn knn ridge depth_nn; do grep -q \",$m,\" \"$2/a/loo.csv\" || { echo \"no $m rows\" >&2; exit 1; }; done; \
hip=$(ls -d \"$2\"/cache/hip-ce20_alpha60-* | grep -v partial | head -1); \
\"$1\" estimator predict --model \"$2/a/model.h5\" --hip \"$hip\" --csv \"$2/predict.csv\" > /dev/null; \
head -1 \"$2/predict.csv\" | grep -qx 'step,estimate,low,high,bordering' || { echo 'predict.csv columns' >&2; exit 1; }; \
test $(wc -l < \"$2/predict.csv\") -eq 7 || { echo 'predict.csv: 6 steps expected' >&2; exit 1; }; \
\"$1\" estimator predict --model \"$2/a/model.h5\" --hip \"$hip\" --method depth_nn --csv \"$2/depth.csv\" > \"$2/depth.log\"; \
grep -q '^impinging: ' \"$2/depth.log\" || { echo 'depth_nn: no impinging line' >&2; exit 1; }; \
test $(wc -l < \"$2/depth.csv\") -eq 7 || { echo 'depth.csv: 6 steps expected' >&2; exit 1; }; \
\"$1\" estimator validate --quick --out \"$2/b\" --cache \"$2/cache\" > \"$2/b.log\" 2>&1; \
cmp \"$2/a/loo.csv\" \"$2/b/loo.csv\" || { echo 'a rerun from the cache changed loo.csv' >&2; exit 1; }"
                   sh $<TARGET_FILE:hipfai> ${estimator_tmp})
  set_tests_properties(cli.estimator_validate_quick PROPERTIES LABELS "cli;slow" TIMEOUT 600)

  # A real hip (the LHDL CT bones with synthesised soft tissue, cli.soft_tissue_real_bones): the
  # quick model predicts it and says how far outside its training hips it lies; its own FE over the
  # same motion (coarse, 6 steps) is added with --fe-hip, and as a training hip it is then interior.
  set(real_hip ${CMAKE_BINARY_DIR}/cli-tmp/soft_tissue_real_bones/out)
  add_test(NAME cli.estimator_real_hip
           COMMAND sh -c "set -e; rm -f \"$2/real.csv\" \"$2/real.h5\" \"$2/real-model.h5\"; \
\"$1\" estimator predict --model \"$2/a/model.h5\" --hip \"$3\" > \"$2/real-before.log\"; \
grep -q 'Mahalanobis distance' \"$2/real-before.log\" || { echo 'predict: no Mahalanobis line' >&2; exit 1; }; \
\"$1\" fem run --model \"$3\" --level coarse --steps 6 --out \"$2/real.h5\" --csv \"$2/real.csv\" > /dev/null 2>&1; \
\"$1\" estimator train --base \"$2/a/model.h5\" --fe-hip \"$3\" \"$2/real.csv\" --out \"$2/real-model.h5\" > \"$2/real-train.log\"; \
grep -q '^trained on 6 hips x 6 steps' \"$2/real-train.log\" || { cat \"$2/real-train.log\"; exit 1; }; \
\"$1\" estimator predict --model \"$2/real-model.h5\" --hip \"$3\" > \"$2/real-after.log\"; \
grep -q '^interior' \"$2/real-after.log\" || { cat \"$2/real-after.log\"; exit 1; }"
                   sh $<TARGET_FILE:hipfai> ${estimator_tmp} ${real_hip})
  set_tests_properties(cli.estimator_real_hip PROPERTIES LABELS "cli;slow" TIMEOUT 600
                       DEPENDS "cli.estimator_validate_quick;cli.soft_tissue_real_bones")
endif()
hipfai_cli_test(NAME estimator_predict_bad_e_prime EXIT nonzero STDERR "--e-prime"
  COMMAND estimator predict --model @TMP@/none.h5 --hip @TMP@ --e-prime most)
