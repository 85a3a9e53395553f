// hipfai — radial tables on disk, so a re-run reuses them (the cache of studies/scene_runner.h).
#pragma once

#include "contact/radial_table.h"

#include <filesystem>
#include <optional>

namespace hipfai::studies {

// Binary little-endian file "HIPFAI-RADIAL-TABLE v1"; written atomically.
void save_radial_table(const contact::RadialTable& table, const std::filesystem::path& path);
// std::nullopt when the file is missing, of another version or damaged (the caller rebuilds).
std::optional<contact::RadialTable> load_radial_table(const std::filesystem::path& path);

}  // namespace hipfai::studies
