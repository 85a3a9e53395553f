// libFuzzer harness of the estimator model reader (studies/estimator_study.h,
// read_estimator_model, an HDF5 file): the bytes are written to a file in the per-process scratch
// folder and read back. Any input must give a model or a hipfai::Error.
#include "core/error.h"
#include "fuzz_scratch.h"
#include "studies/estimator_study.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = hipfai::fuzz::write_scratch_file(
      "model.h5", std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    (void)hipfai::studies::read_estimator_model(file);
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
