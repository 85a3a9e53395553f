// libFuzzer harness of the hip model reader (geometry/hip_model.h, hip_model_from_json: the
// model.json text load_hip_model reads). The tissue files it names are read from a folder holding
// a small mesh under the seeds' names (fuzz_hip_folder.h).
#include "fuzz_hip_folder.h"
#include "fuzz_outcome.h"
#include "geometry/hip_model.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return hipfai::fuzz::parse_or_error([&] {
    (void)hipfai::geometry::hip_model_from_json(std::string(hipfai::fuzz::bytes_of(data, size)),
                                                hipfai::fuzz::hip_folder());
  });
}
