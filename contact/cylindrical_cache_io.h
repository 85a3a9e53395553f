// hipfai — binary save/load of the cylindrical pre-processing (ring table, pose cache), so that a
// study re-run whose inputs did not change reuses them from the on-disk cache instead of
// rebuilding (the runner keys the files by a hash of the inputs; these functions only store and
// restore one artefact each).
//
// File layout (all integers and doubles little-endian, doubles as their IEEE-754 bits, so a loaded
// artefact answers bit-for-bit like the saved one):
//   magic    12 bytes "HIPFAI-CACHE"
//   kind      4 bytes "CYLT" (CylindricalTable) or "CYLP" (CylindricalPoseCache)
//   version   u32 (kCylindricalCacheVersion)
//   size      u64 payload bytes
//   checksum  u64 of the payload (cylindrical_cache_checksum)
//   payload   the object's state (see cylindrical_cache_io.cpp)
// Saving writes `<path>.partial` and renames it onto `path`, so a reader never sees a half-written
// file under the final name (rename is atomic within one file system). Two processes saving the
// same path at the same moment share the `.partial` name; the checksum then rejects a mixed file.
//
// Loading returns std::nullopt, and never crashes, for a missing, unreadable, truncated,
// other-kind, other-version or corrupted file. Besides the checksum, every count is bounded by the
// bytes left in the file before anything is allocated (so the only exception a load can throw is
// std::bad_alloc when memory for a file-sized object is really exhausted), and the restored object is
// checked for the invariants its queries rely on (indices in range, cells consistent with each
// triangle's cell range, crossing ranges inside the crossing arrays, finite coordinates), so even
// a crafted file with a valid checksum cannot make a query read out of bounds.
#pragma once

#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>

namespace hipfai::contact {

// Bump when the payload layout or the meaning of any stored field changes.
inline constexpr std::uint32_t kCylindricalCacheVersion = 1;

// Writes the table (any status) to `path`. Throws hipfai::Error naming the file when it cannot be
// written.
void save_cylindrical_table(const CylindricalTable& table, const std::filesystem::path& path);
// The saved table, or std::nullopt (see above).
std::optional<CylindricalTable> load_cylindrical_table(const std::filesystem::path& path);

// Writes the pose cache (any status, with its query options) to `path`. Throws hipfai::Error
// naming the file when it cannot be written.
void save_pose_cache(const CylindricalPoseCache& cache, const std::filesystem::path& path);
// The saved pose cache, or std::nullopt (see above).
std::optional<CylindricalPoseCache> load_pose_cache(const std::filesystem::path& path);

// 64-bit checksum of a payload as stored in the header (exposed so tests can craft files whose
// checksum is right but whose content is not).
std::uint64_t cylindrical_cache_checksum(std::span<const std::byte> payload);

}  // namespace hipfai::contact
