// libFuzzer harness of the scene YAML reader (studies/scene.h, parse_scene: the text read_scene
// reads): any input must give a scene or a hipfai::Error. Relative paths in the scene resolve
// into the per-process scratch folder.
#include "core/error.h"
#include "fuzz_scratch.h"
#include "studies/scene.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)hipfai::studies::parse_scene(text, hipfai::fuzz::scratch_dir() / "scene.yaml");
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
