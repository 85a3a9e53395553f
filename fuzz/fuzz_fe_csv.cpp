// libFuzzer harness of the FE run's per-step table reader (studies/results/hip_fe_table.h,
// read_hip_fe_csv: fe.csv of an FE cache entry or a sweep's <model>.csv, which the validation
// study and the estimator's FE sweep read): the bytes are written to a scratch file and read.
#include "fuzz_outcome.h"
#include "fuzz_scratch.h"
#include "studies/results/hip_fe_table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = hipfai::fuzz::write_scratch_file("fe.csv", hipfai::fuzz::bytes_of(data, size));
  return hipfai::fuzz::parse_or_error([&] { (void)hipfai::studies::read_hip_fe_csv(file); });
}
