// The folder the hip-description harnesses (model.json, hip.json) read their tissue meshes from:
// the tetrahedron under every file name their seeds give (the generated hips' <tissue>.ply and
// the segmented hip's meshes/real-hips/LHDL_CT names), written once into the scratch folder.
#pragma once

#include <filesystem>

namespace hipfai::fuzz {

const std::filesystem::path& hip_folder();

}  // namespace hipfai::fuzz
