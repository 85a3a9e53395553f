// libFuzzer harness of the results-file readers (studies/results_file.h: read_dataset and
// read_string_attribute, which reports and the estimator's FE sweep use on a study's .h5): the
// bytes are written to a file in the per-process scratch folder, then every dataset and attribute
// of the seed is read (fuzz_results_reads.h).
#include "fuzz_outcome.h"
#include "fuzz_results_reads.h"
#include "fuzz_scratch.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file =
      hipfai::fuzz::write_scratch_file("results.h5", hipfai::fuzz::bytes_of(data, size));
  return hipfai::fuzz::parse_or_error([&] { hipfai::fuzz::read_results_file(file); });
}
