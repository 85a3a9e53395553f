// libFuzzer harness of the results-file readers (studies/results_file.h: read_dataset and
// read_string_attribute, which reports and the estimator's FE sweep use on a study's .h5): the
// bytes are written to a file in the per-process scratch folder, then every dataset and attribute
// of the seed is read (fuzz_results_reads.h). Each read must give its value or a hipfai::Error.
#include "core/error.h"
#include "fuzz_results_reads.h"
#include "fuzz_scratch.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = hipfai::fuzz::write_scratch_file(
      "results.h5", std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    hipfai::fuzz::read_results_file(file);
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
