#include "fuzz_hip_folder.h"

#include "fuzz_scratch.h"
#include "fuzz_tetrahedron.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_io.h"

#include <string>

namespace hipfai::fuzz {
namespace {

std::filesystem::path make_hip_folder() {
  const std::filesystem::path dir = scratch_dir() / "hip";
  std::filesystem::create_directories(dir);
  const geometry::TriMesh mesh = tetrahedron();
  for (const char* tissue : geometry::kHipTissueNames)
    geometry::write_mesh(mesh, dir / (std::string(tissue) + ".ply"));
  for (const char* file : {"femur_r.ply", "pelvis_no_sacrum.ply"})
    geometry::write_mesh(mesh, dir / file);
  return dir;
}

}  // namespace

const std::filesystem::path& hip_folder() {
  static const std::filesystem::path dir = make_hip_folder();
  return dir;
}

}  // namespace hipfai::fuzz
