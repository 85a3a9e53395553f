// libFuzzer harness of the scene YAML reader (studies/pipeline/scene.h, parse_scene: the text read_scene
// reads). Relative paths in the scene resolve into the per-process scratch folder.
#include "fuzz_outcome.h"
#include "fuzz_scratch.h"
#include "studies/pipeline/scene.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return hipfai::fuzz::parse_or_error([&] {
    (void)hipfai::studies::parse_scene(std::string(hipfai::fuzz::bytes_of(data, size)),
                                       hipfai::fuzz::scratch_dir() / "scene.yaml");
  });
}
