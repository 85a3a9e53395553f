# estimator sample: bad input is a one-line error and a non-zero exit, before any hip is made.
hipfai_cli_test(NAME estimator_sample_n_zero EXIT nonzero STDERR "--n 0 must be at least 1"
  COMMAND estimator sample --n 0 --out @TMP@/out)
hipfai_cli_test(NAME estimator_sample_unknown_design EXIT nonzero STDERR "unknown design 'halton' \\(known: lhs, sobol\\)"
  COMMAND estimator sample --n 3 --design halton --out @TMP@/out)
hipfai_cli_test(NAME estimator_sample_unknown_parameter EXIT nonzero STDERR "unknown parameter 'labrum' to vary"
  COMMAND estimator sample --n 3 --vary ce,labrum --out @TMP@/out)
hipfai_cli_test(NAME estimator_sample_negative_held_out EXIT nonzero STDERR "--held-out -2 must be 0 or more"
  COMMAND estimator sample --n 3 --held-out -2 --out @TMP@/out)

# estimator refine: bad input is a one-line error before any model is read.
hipfai_cli_test(NAME estimator_refine_unknown_criterion EXIT nonzero STDERR "unknown criterion 'entropy' \\(known: width, disagreement\\)"
  COMMAND estimator refine --model @TMP@/none.h5 --candidates @TMP@ --criterion entropy)
hipfai_cli_test(NAME estimator_refine_budget_zero EXIT nonzero STDERR "--budget 0 must be at least 1"
  COMMAND estimator refine --model @TMP@/none.h5 --candidates @TMP@ --budget 0)
