// libFuzzer harness of the estimator model reader (studies/estimator_study.h,
// read_estimator_model, an HDF5 file): the bytes are written to a file in the per-process scratch
// folder and read back.
#include "fuzz_outcome.h"
#include "fuzz_scratch.h"
#include "studies/estimator_study.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file =
      hipfai::fuzz::write_scratch_file("model.h5", hipfai::fuzz::bytes_of(data, size));
  return hipfai::fuzz::parse_or_error([&] { (void)hipfai::studies::read_estimator_model(file); });
}
