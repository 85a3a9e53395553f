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
