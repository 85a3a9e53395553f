// libFuzzer harness of one mesh reader (the format chosen at compile time, fuzz/CMakeLists.txt):
// any input must give a mesh or a hipfai::Error. Any other exception, a crash, a sanitizer report,
// a leak or a runaway allocation is a finding.
#include "core/error.h"
#include "geometry/mesh_io_msh.h"
#include "geometry/mesh_io_obj.h"
#include "geometry/mesh_io_ply.h"
#include "geometry/mesh_io_stl.h"
#include "geometry/mesh_io_vtp.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
#if defined(HIPFAI_FUZZ_FORMAT_stl)
    (void)hipfai::geometry::mesh_io::read_stl("fuzz.stl", bytes);
#elif defined(HIPFAI_FUZZ_FORMAT_ply)
    (void)hipfai::geometry::mesh_io::read_ply("fuzz.ply", bytes);
#elif defined(HIPFAI_FUZZ_FORMAT_obj)
    (void)hipfai::geometry::mesh_io::read_obj("fuzz.obj", bytes);
#elif defined(HIPFAI_FUZZ_FORMAT_vtp)
    (void)hipfai::geometry::mesh_io::read_vtp("fuzz.vtp", bytes);
#elif defined(HIPFAI_FUZZ_FORMAT_msh)
    (void)hipfai::geometry::mesh_io::read_msh("fuzz.msh", bytes);
#else
#error "define HIPFAI_FUZZ_FORMAT_<format>"
#endif
  } catch (const hipfai::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
