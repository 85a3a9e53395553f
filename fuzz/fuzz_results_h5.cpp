// libFuzzer harness of the results-file reader (studies/results/results_file.h: ResultsReader, behind
// read_dataset and read_string_attribute, which reports and the estimator's FE sweep use on a
// study's .h5): the bytes are written to a file in the per-process scratch folder, then every
// dataset and attribute of the seed is read, all in one child process (fuzz_results_reads.h).
#include "fuzz_outcome.h"
#include "fuzz_results_reads.h"
#include "fuzz_scratch.h"
#include "studies/results/hdf5_child.h"

// HDF5 runs in a child process with a time limit (studies/results/hdf5_child.h): under libFuzzer's own
// 10 s per input, so that a file HDF5 loops on is the reader's refusal, not a timeout here.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hipfai::studies::set_hdf5_child_seconds(5);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file =
      hipfai::fuzz::write_scratch_file("results.h5", hipfai::fuzz::bytes_of(data, size));
  return hipfai::fuzz::parse_or_error([&] { hipfai::fuzz::read_results_file(file); });
}
