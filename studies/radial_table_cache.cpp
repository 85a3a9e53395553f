#include "studies/radial_table_cache.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <cstdint>
#include <cstring>
#include <fstream>

namespace hipfai::studies {

namespace {

// The version names the table's CONTENT, not only the layout: v2 tables bin triangles whose plane
// passes (nearly) through the centre along their great-circle arc; a v1 file has
// the same layout but lists them as always-candidates, which is correct but far slower, so it is
// rejected and rebuilt. Bump the version whenever build_radial_table puts triangles elsewhere.
constexpr char kMagic[] = "HIPFAI-RADIAL-TABLE v2";

template <typename T>
void put(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

template <typename T>
void put_vector(std::ostream& out, const std::vector<T>& values) {
  put(out, static_cast<std::uint64_t>(values.size()));
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(T)));
}

template <typename T>
bool get(std::istream& in, T& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof value));
}

template <typename T>
bool get_vector(std::istream& in, std::vector<T>& values, std::uint64_t limit) {
  std::uint64_t size = 0;
  if (!get(in, size) || size > limit) return false;
  values.resize(size);
  return static_cast<bool>(
      in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(size * sizeof(T))));
}

}  // namespace

void save_radial_table(const contact::RadialTable& table, const std::filesystem::path& path) {
  std::filesystem::create_directories(path.parent_path());
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(kMagic, sizeof kMagic);
    put(out, static_cast<std::int32_t>(table.grid.mapping));
    put(out, static_cast<std::int32_t>(table.grid.dimension));
    put(out, static_cast<std::int32_t>(table.grid.faces));
    put(out, table.centre.x());
    put(out, table.centre.y());
    put(out, table.centre.z());
    put(out, static_cast<std::uint64_t>(table.num_triangles));
    put(out, static_cast<std::uint64_t>(table.cells.size()));
    for (const auto& cell : table.cells) put_vector(out, cell);
    put_vector(out, table.always_candidates);
    put(out, static_cast<std::uint64_t>(table.triangle_cells.size()));
    for (const auto& cells : table.triangle_cells) put_vector(out, cells);
    put_vector(out, table.is_always);
  });
}

std::optional<contact::RadialTable> load_radial_table(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  char magic[sizeof kMagic];
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
    return std::nullopt;
  }
  contact::RadialTable table;
  std::int32_t mapping = 0, dimension = 0, faces = 0;
  double x = 0, y = 0, z = 0;
  std::uint64_t num_triangles = 0, num_cells = 0, num_triangle_cells = 0;
  // Sizes are bounded so a damaged file cannot ask for absurd allocations.
  constexpr std::uint64_t kLimit = std::uint64_t{1} << 32;
  if (!get(in, mapping) || !get(in, dimension) || !get(in, faces) || !get(in, x) || !get(in, y) ||
      !get(in, z) || !get(in, num_triangles) || !get(in, num_cells) || num_cells > kLimit ||
      mapping < 0 || mapping > 2) {
    return std::nullopt;
  }
  table.grid.mapping = static_cast<contact::RadialMapping>(mapping);
  table.grid.dimension = dimension;
  table.grid.faces = faces;
  if (static_cast<std::uint64_t>(table.grid.num_cells()) != num_cells) return std::nullopt;
  table.centre = contact::Vec3(x, y, z);
  table.num_triangles = num_triangles;
  table.cells.resize(num_cells);
  for (auto& cell : table.cells) {
    if (!get_vector(in, cell, num_triangles)) return std::nullopt;
  }
  if (!get_vector(in, table.always_candidates, num_triangles)) return std::nullopt;
  if (!get(in, num_triangle_cells) || num_triangle_cells != num_triangles) return std::nullopt;
  table.triangle_cells.resize(num_triangle_cells);
  for (auto& cells : table.triangle_cells) {
    if (!get_vector(in, cells, num_cells)) return std::nullopt;
  }
  if (!get_vector(in, table.is_always, num_triangles)) return std::nullopt;
  return table;
}

}  // namespace hipfai::studies
