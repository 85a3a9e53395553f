// libFuzzer harness of the OpenSim motion reader (anatomy/opensim_motion.h,
// parse_opensim_motion: the text read_opensim_motion reads). Named .mot, so the SIMM units rule
// is reachable; no side given, so the side choice runs too.
#include "anatomy/opensim_motion.h"
#include "fuzz_outcome.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return hipfai::fuzz::parse_or_error([&] {
    (void)hipfai::anatomy::parse_opensim_motion(std::string(hipfai::fuzz::bytes_of(data, size)), "fuzz.mot");
  });
}
