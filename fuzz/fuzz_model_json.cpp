// libFuzzer harness of the hip model reader (geometry/hip_model.h, hip_model_from_json: the
// model.json text load_hip_model reads): any input must give a model or a hipfai::Error. The
// tissue files it names are read from a folder holding a small mesh under the seeds' names.
#include "core/error.h"
#include "fuzz_hip_folder.h"
#include "geometry/hip_model.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)hipfai::geometry::hip_model_from_json(text, hipfai::fuzz::hip_folder());
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
