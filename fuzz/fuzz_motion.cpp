// libFuzzer harness of the motion CSV reader (studies/motion.h, parse_motion_csv: the text
// read_motion_csv reads): any input must give a motion or a hipfai::Error.
#include "core/error.h"
#include "studies/motion.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)hipfai::studies::parse_motion_csv(text, "fuzz.csv");
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
