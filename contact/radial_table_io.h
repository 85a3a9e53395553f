// hipfai — radial tables on disk, so a re-run reuses them (contact/penetrate.h keeps them in the request's cache folder).
#pragma once

#include "contact/radial_table.h"

#include <filesystem>
#include <optional>

namespace hipfai::contact {

// Binary little-endian file "HIPFAI-RADIAL-TABLE v2"; written atomically. The version changes with
// the table's content (how triangles are binned), so a file of an older build is not loaded and the
// cache rebuilds it at the same path.
void save_radial_table(const contact::RadialTable& table, const std::filesystem::path& path);
// std::nullopt when the file is missing, of another version (e.g. v1) or damaged (the caller rebuilds):
// every count is bounded by the bytes left before anything is allocated, and a table is returned
// only when its indices are in range and its two directions of binning agree, so a damaged file
// cannot make a query read out of bounds.
std::optional<contact::RadialTable> load_radial_table(const std::filesystem::path& path);

}  // namespace hipfai::contact
