// libFuzzer harness of the segmented hip reader (studies/pipeline/segmented_hip.h, segmented_hip_from_json:
// the hip.json text load_segmented_hip reads). The meshes it names are read from a folder holding
// a small mesh under the seeds' names (fuzz_hip_folder.h).
#include "fuzz_hip_folder.h"
#include "fuzz_outcome.h"
#include "studies/pipeline/segmented_hip.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return hipfai::fuzz::parse_or_error([&] {
    (void)hipfai::studies::segmented_hip_from_json(std::string(hipfai::fuzz::bytes_of(data, size)),
                                                   hipfai::fuzz::hip_folder());
  });
}
