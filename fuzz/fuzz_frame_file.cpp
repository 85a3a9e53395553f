// libFuzzer harness of the user frame reader (anatomy/frame_file.h, parse_frame_file: the text
// read_frame_file reads; the three shapes: axes, landmarks, a hip model.json).
#include "anatomy/frame_file.h"
#include "fuzz_outcome.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return hipfai::fuzz::parse_or_error([&] {
    (void)hipfai::anatomy::parse_frame_file(std::string(hipfai::fuzz::bytes_of(data, size)), "fuzz.json");
  });
}
