// libFuzzer harness of the estimator model reader (studies/estimator_study.h,
// read_estimator_model, an HDF5 file): the bytes are written to a file in the per-process scratch
// folder and read back.
#include "fuzz_outcome.h"
#include "fuzz_scratch.h"
#include "studies/results/hdf5_child.h"
#include "studies/estimator_model_file.h"

// HDF5 runs in a child process with a time limit (studies/results/hdf5_child.h): under libFuzzer's own
// 10 s per input, so that a file HDF5 loops on is the reader's refusal, not a timeout here.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hipfai::studies::set_hdf5_child_seconds(5);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file =
      hipfai::fuzz::write_scratch_file("model.h5", hipfai::fuzz::bytes_of(data, size));
  return hipfai::fuzz::parse_or_error([&] { (void)hipfai::studies::read_estimator_model(file); });
}
