// libFuzzer harness of the segmented hip reader (studies/segmented_hip.h, segmented_hip_from_json:
// the hip.json text load_segmented_hip reads): any input must give a model or a hipfai::Error. The
// meshes it names are read from a folder holding a small mesh under the seeds' names.
#include "core/error.h"
#include "fuzz_hip_folder.h"
#include "studies/segmented_hip.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)hipfai::studies::segmented_hip_from_json(text, hipfai::fuzz::hip_folder());
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
