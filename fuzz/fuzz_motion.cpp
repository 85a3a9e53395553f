// libFuzzer harness of the motion CSV reader (studies/pipeline/motion.h, parse_motion_csv: the text
// read_motion_csv reads).
#include "fuzz_outcome.h"
#include "studies/pipeline/motion.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return hipfai::fuzz::parse_or_error([&] {
    (void)hipfai::studies::parse_motion_csv(std::string(hipfai::fuzz::bytes_of(data, size)),
                                            "fuzz.csv");
  });
}
