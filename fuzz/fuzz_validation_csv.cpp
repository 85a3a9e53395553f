// libFuzzer harness of the validation study's stored results reader (studies/
// validation_results_file.h, read_validation_results: the folder `hipfai report correlation`
// reads). One input is both files: the bytes before the first form feed (\f) are steps.csv, the
// rest (when there is a \f) timings.csv; both are written to a scratch folder and read.
#include "fuzz_outcome.h"
#include "fuzz_scratch.h"
#include "studies/results/validation_results_file.h"

#include <filesystem>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes = hipfai::fuzz::bytes_of(data, size);
  const std::size_t split = bytes.find('\f');
  const auto steps = hipfai::fuzz::write_scratch_file("steps.csv", bytes.substr(0, split));
  const auto timings = steps.parent_path() / "timings.csv";
  if (split == std::string_view::npos) {
    std::filesystem::remove(timings);
  } else {
    (void)hipfai::fuzz::write_scratch_file("timings.csv", bytes.substr(split + 1));
  }
  return hipfai::fuzz::parse_or_error(
      [&] { (void)hipfai::studies::read_validation_results(steps.parent_path()); });
}
