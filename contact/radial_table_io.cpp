#include "contact/radial_table_io.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::contact {

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

// A cursor over the file's bytes: every read is bounded by what is left, so a count in a damaged
// file cannot ask for more memory than the file could fill.
class TableReader {
 public:
  explicit TableReader(std::string bytes) : bytes_(std::move(bytes)) {}
  std::size_t left() const { return bytes_.size() - at_; }
  template <typename T>
  bool get(T& value) {
    if (left() < sizeof value) return false;
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return true;
  }
  template <typename T>
  bool get_vector(std::vector<T>& values) {
    std::uint64_t size = 0;
    if (!get(size) || size > left() / sizeof(T)) return false;
    values.resize(static_cast<std::size_t>(size));
    if (size > 0) std::memcpy(values.data(), bytes_.data() + at_, static_cast<std::size_t>(size) * sizeof(T));
    at_ += static_cast<std::size_t>(size) * sizeof(T);
    return true;
  }

 private:
  std::string bytes_;
  std::size_t at_ = 0;
};

int faces_of(contact::RadialMapping mapping) {
  switch (mapping) {
    case contact::RadialMapping::kSpherical: return 1;
    case contact::RadialMapping::kCartesian: return 2;
    case contact::RadialMapping::kCube: return 6;
  }
  return 0;
}

bool all_below(const std::vector<std::int32_t>& indices, std::uint64_t end) {
  return std::all_of(indices.begin(), indices.end(),
                     [end](std::int32_t i) { return i >= 0 && static_cast<std::uint64_t>(i) < end; });
}

// What the queries and updates rely on: indices in range, the two directions of the binning
// (cell -> triangles, triangle -> cells) the same pairs, the always-candidates those flagged.
bool consistent(const contact::RadialTable& table) {
  const std::uint64_t triangles = table.num_triangles, cells = table.cells.size();
  if (table.triangle_cells.size() != triangles || table.is_always.size() != triangles) return false;
  if (!all_below(table.always_candidates, triangles)) return false;
  std::vector<std::pair<std::int32_t, std::int32_t>> by_cell, by_triangle;  // (triangle, cell)
  for (std::size_t c = 0; c < cells; ++c) {
    if (!all_below(table.cells[c], triangles)) return false;
    for (const std::int32_t t : table.cells[c]) by_cell.emplace_back(t, static_cast<std::int32_t>(c));
  }
  for (std::size_t t = 0; t < triangles; ++t) {
    if (!all_below(table.triangle_cells[t], cells)) return false;
    for (const std::int32_t c : table.triangle_cells[t]) by_triangle.emplace_back(static_cast<std::int32_t>(t), c);
  }
  std::sort(by_cell.begin(), by_cell.end());
  std::sort(by_triangle.begin(), by_triangle.end());
  if (by_cell != by_triangle) return false;
  std::vector<std::uint8_t> flagged(static_cast<std::size_t>(triangles), 0);
  for (const std::int32_t t : table.always_candidates) {
    if (flagged[static_cast<std::size_t>(t)]++ != 0) return false;  // listed twice
  }
  return flagged == table.is_always;
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
  std::ostringstream content;
  content << in.rdbuf();
  TableReader file(content.str());
  char magic[sizeof kMagic];
  if (!file.get(magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0) return std::nullopt;
  contact::RadialTable table;
  std::int32_t mapping = 0, dimension = 0, faces = 0;
  double x = 0, y = 0, z = 0;
  std::uint64_t num_triangles = 0, num_cells = 0, num_triangle_cells = 0;
  if (!file.get(mapping) || !file.get(dimension) || !file.get(faces) || !file.get(x) || !file.get(y) ||
      !file.get(z) || !file.get(num_triangles) || !file.get(num_cells) || mapping < 0 || mapping > 2) {
    return std::nullopt;
  }
  table.grid.mapping = static_cast<contact::RadialMapping>(mapping);
  // Each cell and each triangle stores at least its 8-byte count; the grid is the mapping's.
  const std::uint64_t counts = file.left() / 8;
  if (faces != faces_of(table.grid.mapping) || dimension < 1 || static_cast<std::uint64_t>(dimension) > counts ||
      num_cells != static_cast<std::uint64_t>(faces) * static_cast<std::uint64_t>(dimension) * static_cast<std::uint64_t>(dimension) ||
      num_cells > counts || num_triangles > counts ||
      num_triangles > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()) ||
      !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
    return std::nullopt;
  }
  table.grid.dimension = dimension;
  table.grid.faces = faces;
  table.centre = contact::Vec3(x, y, z);
  table.num_triangles = static_cast<std::size_t>(num_triangles);
  table.cells.resize(static_cast<std::size_t>(num_cells));
  for (auto& cell : table.cells) {
    if (!file.get_vector(cell)) return std::nullopt;
  }
  if (!file.get_vector(table.always_candidates)) return std::nullopt;
  if (!file.get(num_triangle_cells) || num_triangle_cells != num_triangles) return std::nullopt;
  table.triangle_cells.resize(static_cast<std::size_t>(num_triangle_cells));
  for (auto& cells : table.triangle_cells) {
    if (!file.get_vector(cells)) return std::nullopt;
  }
  if (!file.get_vector(table.is_always) || file.left() != 0 || !consistent(table)) return std::nullopt;
  return table;
}

}  // namespace hipfai::contact
