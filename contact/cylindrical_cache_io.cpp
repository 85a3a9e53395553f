#include "contact/cylindrical_cache_io.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

namespace hipfai::contact {
namespace {

constexpr std::array<char, 12> kMagic = {'H', 'I', 'P', 'F', 'A', 'I', '-', 'C', 'A', 'C', 'H', 'E'};
constexpr std::array<char, 4> kTableKind = {'C', 'Y', 'L', 'T'};
constexpr std::array<char, 4> kPoseCacheKind = {'C', 'Y', 'L', 'P'};
constexpr std::size_t kHeaderBytes = 12 + 4 + 4 + 8 + 8;

// Appends little-endian values whatever the host's byte order (shifts, not memcpy of integers).
class Writer {
 public:
  void u8(std::uint8_t value) { bytes_.push_back(static_cast<std::byte>(value)); }
  void u32(std::uint32_t value) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(value >> (8 * i)));
  }
  void u64(std::uint64_t value) {
    for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(value >> (8 * i)));
  }
  void i32(std::int32_t value) { u32(static_cast<std::uint32_t>(value)); }
  void i64(long long value) { u64(static_cast<std::uint64_t>(value)); }
  void f64(double value) { u64(std::bit_cast<std::uint64_t>(value)); }
  void vec3(const Vec3& value) {
    f64(value.x());
    f64(value.y());
    f64(value.z());
  }
  void string(const std::string& value) {
    u64(value.size());
    for (char c : value) u8(static_cast<std::uint8_t>(c));
  }
  template <std::size_t N>
  void tag(const std::array<char, N>& value) {
    for (char c : value) u8(static_cast<std::uint8_t>(c));
  }
  std::vector<std::byte>& bytes() { return bytes_; }

 private:
  std::vector<std::byte> bytes_;
};

// Bounds-checked little-endian reads: after any failed read ok() is false and every further read
// returns zeros, so parsing code can check once per block instead of after every field.
class CacheReader {
 public:
  explicit CacheReader(std::span<const std::byte> bytes) : bytes_(bytes) {}

  bool ok() const { return ok_; }
  void fail() { ok_ = false; }
  std::size_t remaining() const { return ok_ ? bytes_.size() - position_ : 0; }
  // True when `count` items of `item_bytes` each can still be in the file: the bound that keeps
  // a corrupted count from allocating more than the file could describe.
  bool can_hold(std::uint64_t count, std::size_t item_bytes) {
    if (!ok_ || count > remaining() / item_bytes) ok_ = false;
    return ok_;
  }

  std::uint8_t u8() {
    if (!can_hold(1, 1)) return 0;
    return static_cast<std::uint8_t>(bytes_[position_++]);
  }
  std::uint32_t u32() {
    if (!can_hold(1, 4)) return 0;
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) value |= static_cast<std::uint32_t>(u8()) << (8 * i);
    return value;
  }
  std::uint64_t u64() {
    if (!can_hold(1, 8)) return 0;
    std::uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= static_cast<std::uint64_t>(u8()) << (8 * i);
    return value;
  }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  long long i64() { return static_cast<long long>(u64()); }
  double f64() { return std::bit_cast<double>(u64()); }
  Vec3 vec3() {
    const double x = f64();
    const double y = f64();
    const double z = f64();
    return {x, y, z};
  }
  std::string string() {
    const std::uint64_t size = u64();
    if (!can_hold(size, 1)) return {};
    std::string value(static_cast<std::size_t>(size), '\0');
    for (char& c : value) c = static_cast<char>(u8());
    return value;
  }
  template <std::size_t N>
  bool tag_is(const std::array<char, N>& expected) {
    bool same = true;
    for (char c : expected) same = (static_cast<char>(u8()) == c) && same;
    return ok_ && same;
  }
  // A count of items of at least `item_bytes` each, or 0 with ok() false if the file cannot
  // hold that many.
  std::size_t count(std::size_t item_bytes) {
    const std::uint64_t n = u64();
    if (!can_hold(n, item_bytes)) return 0;
    return static_cast<std::size_t>(n);
  }

 private:
  std::span<const std::byte> bytes_;
  std::size_t position_ = 0;
  bool ok_ = true;
};

bool finite(const Vec3& value) { return value.allFinite(); }

std::uint8_t encode_status(QueryStatus status) {
  switch (status) {
    case QueryStatus::kOk: return 0;
    case QueryStatus::kNoOverlap: return 1;
    case QueryStatus::kInvalidInput: return 2;
  }
  return 2;
}

std::optional<QueryStatus> decode_status(std::uint8_t code) {
  switch (code) {
    case 0: return QueryStatus::kOk;
    case 1: return QueryStatus::kNoOverlap;
    case 2: return QueryStatus::kInvalidInput;
    default: return std::nullopt;
  }
}

// Header + payload, written to `<path>.partial` and renamed onto `path`.
void write_file(const std::array<char, 4>& kind, std::vector<std::byte>& payload,
                const std::filesystem::path& path, const char* what) {
  Writer header;
  header.tag(kMagic);
  header.tag(kind);
  header.u32(kCylindricalCacheVersion);
  header.u64(payload.size());
  header.u64(cylindrical_cache_checksum(payload));
  try {
    write_file_atomically(path, [&](std::ostream& out) {
      out.write(reinterpret_cast<const char*>(header.bytes().data()),
                static_cast<std::streamsize>(header.bytes().size()));
      out.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    });
  } catch (const Error& e) {
    throw_error(what, ": ", e.what());  // keep naming the table being saved
  }
}

// The payload of a file of this kind and version whose checksum matches, or nullopt.
std::optional<std::vector<std::byte>> read_payload(const std::array<char, 4>& kind,
                                                   const std::filesystem::path& path) {
  std::error_code error;
  const std::uintmax_t file_bytes = std::filesystem::file_size(path, error);
  if (error || file_bytes < kHeaderBytes ||
      file_bytes > static_cast<std::uintmax_t>(std::numeric_limits<std::streamsize>::max())) {
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::array<std::byte, kHeaderBytes> header_bytes{};
  if (!in.read(reinterpret_cast<char*>(header_bytes.data()), kHeaderBytes)) return std::nullopt;
  CacheReader header(header_bytes);
  if (!header.tag_is(kMagic) || !header.tag_is(kind)) return std::nullopt;
  if (header.u32() != kCylindricalCacheVersion) return std::nullopt;
  const std::uint64_t payload_bytes = header.u64();
  const std::uint64_t checksum = header.u64();
  // Equal to the file's own size, so the allocation below is bounded by what is on disk.
  if (!header.ok() || payload_bytes != file_bytes - kHeaderBytes) return std::nullopt;
  std::vector<std::byte> payload(static_cast<std::size_t>(payload_bytes));
  if (!in.read(reinterpret_cast<char*>(payload.data()), static_cast<std::streamsize>(payload.size()))) {
    return std::nullopt;
  }
  if (cylindrical_cache_checksum(payload) != checksum) return std::nullopt;
  return payload;
}

}  // namespace

std::uint64_t cylindrical_cache_checksum(std::span<const std::byte> payload) {
  // FNV-1a on 64-bit words (bytes for the tail). Each step h -> (h ^ w) * odd is a bijection of
  // h, so changing any single word always changes the result; multi-word corruption collides
  // with probability ~2^-64.
  constexpr std::uint64_t kOffset = 14695981039346656037ull;
  constexpr std::uint64_t kPrime = 1099511628211ull;
  std::uint64_t hash = kOffset ^ payload.size();
  std::size_t i = 0;
  for (; i + 8 <= payload.size(); i += 8) {
    std::uint64_t word = 0;
    for (int b = 0; b < 8; ++b) word |= static_cast<std::uint64_t>(payload[i + static_cast<std::size_t>(b)]) << (8 * b);
    hash = (hash ^ word) * kPrime;
  }
  for (; i < payload.size(); ++i) hash = (hash ^ static_cast<std::uint64_t>(payload[i])) * kPrime;
  return hash ^ (hash >> 29);
}

namespace detail {

class CylindricalCacheAccess {
 public:
  static void write_table(const CylindricalTable& table, Writer& out) {
    out.u8(encode_status(table.status_));
    out.string(table.message_);
    out.vec3(table.frame_.centre);
    out.vec3(table.frame_.axis);
    out.vec3(table.frame_.e1);
    out.vec3(table.frame_.e2);
    for (double value : {table.r_lo_, table.r_hi_, table.z_lo_, table.z_hi_, table.res_r_,
                         table.res_z_, table.pad_, table.l_min_, table.l_max_}) {
      out.f64(value);
    }
    out.i64(table.num_r_);
    out.i64(table.num_z_);
    out.i32(table.neighbour_cells_);
    out.u64(table.local_vertices_.size());
    for (const Vec3& p : table.local_vertices_) out.vec3(p);
    out.u64(table.triangles_.size());
    for (std::size_t t = 0; t < table.triangles_.size(); ++t) {
      for (std::int32_t v : table.triangles_[t]) out.i32(v);
      out.vec3(table.local_normals_[t]);
      const CylindricalTable::CellRange& range = table.ranges_[t];
      // Cell indices fit in 32 bits (num_r, num_z < 2^31 is checked on load).
      out.i32(static_cast<std::int32_t>(range.r0));
      out.i32(static_cast<std::int32_t>(range.r1));
      out.i32(static_cast<std::int32_t>(range.z0));
      out.i32(static_cast<std::int32_t>(range.z1));
      out.u8(range.overflow ? 1 : 0);
    }
    // Cells in storage order with their lists in order: the order of candidates is kept, so
    // ties between equal crossings resolve exactly as in the saved table.
    out.u64(table.cells_.size());
    for (const auto& cell : table.cells_) out.u32(static_cast<std::uint32_t>(cell.size()));
    for (const auto& cell : table.cells_) {
      for (std::int32_t t : cell) out.i32(t);
    }
    out.u64(table.overflow_.size());
    for (std::int32_t t : table.overflow_) out.i32(t);
  }

  static std::optional<CylindricalTable> read_table(CacheReader& in) {
    CylindricalTable table;
    if (!read_grid(in, table)) return std::nullopt;
    const std::size_t num_vertices = in.count(3 * 8);
    table.local_vertices_.resize(num_vertices);
    for (Vec3& p : table.local_vertices_) {
      p = in.vec3();
      if (!finite(p)) return std::nullopt;
    }
    if (!read_triangles(in, num_vertices, table)) return std::nullopt;
    if (!read_cells(in, table)) return std::nullopt;
    if (!read_overflow(in, table)) return std::nullopt;
    if (!in.ok()) return std::nullopt;
    for (std::size_t t = 0; t < table.triangles_.size(); ++t) table.refresh_triangle_plane(static_cast<std::int32_t>(t));
    table.build_angular_index();
    return table;
  }

  // Status, frame and grid; false when any is unreadable or meaningless.
  static bool read_grid(CacheReader& in, CylindricalTable& table) {
    const std::optional<QueryStatus> status = decode_status(in.u8());
    if (!status) return false;
    table.status_ = *status;
    table.message_ = in.string();
    table.frame_.centre = in.vec3();
    table.frame_.axis = in.vec3();
    table.frame_.e1 = in.vec3();
    table.frame_.e2 = in.vec3();
    for (double* value : {&table.r_lo_, &table.r_hi_, &table.z_lo_, &table.z_hi_, &table.res_r_,
                          &table.res_z_, &table.pad_, &table.l_min_, &table.l_max_}) {
      *value = in.f64();
      if (!std::isfinite(*value)) return false;
    }
    table.num_r_ = in.i64();
    table.num_z_ = in.i64();
    table.neighbour_cells_ = in.i32();
    return in.ok() && finite(table.frame_.centre) && finite(table.frame_.axis) && finite(table.frame_.e1) &&
           finite(table.frame_.e2) && table.res_r_ > 0.0 && table.res_z_ > 0.0 && table.neighbour_cells_ >= 0 &&
           table.num_r_ >= 0 && table.num_z_ >= 0 && table.num_r_ <= std::numeric_limits<std::int32_t>::max() &&
           table.num_z_ <= std::numeric_limits<std::int32_t>::max();
  }

  // Triangles: vertex indices, normal and cell range each.
  static bool read_triangles(CacheReader& in, std::size_t num_vertices, CylindricalTable& table) {
    const std::size_t num_triangles = in.count(3 * 4 + 3 * 8 + 4 * 4 + 1);
    if (!in.ok() || num_triangles > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
      return false;
    }
    table.triangles_.resize(num_triangles);
    table.local_normals_.resize(num_triangles);
    table.planes_.resize(num_triangles);
    table.ranges_.resize(num_triangles);
    for (std::size_t t = 0; t < num_triangles; ++t) {
      for (std::int32_t& v : table.triangles_[t]) {
        v = in.i32();
        if (v < 0 || static_cast<std::size_t>(v) >= num_vertices) return false;
      }
      table.local_normals_[t] = in.vec3();
      CylindricalTable::CellRange& range = table.ranges_[t];
      range.r0 = in.i32();
      range.r1 = in.i32();
      range.z0 = in.i32();
      range.z1 = in.i32();
      const std::uint8_t overflow = in.u8();
      if (!in.ok() || overflow > 1 || !finite(table.local_normals_[t])) return false;
      range.overflow = overflow == 1;
      // Either the empty range of a triangle outside the grid, or a range inside the grid.
      const bool empty = range.r0 == 0 && range.r1 == -1 && range.z0 == 0 && range.z1 == -1;
      const bool inside = range.r0 >= 0 && range.r0 <= range.r1 && range.r1 < table.num_r_ &&
                          range.z0 >= 0 && range.z0 <= range.z1 && range.z1 < table.num_z_;
      if (!empty && !inside) return false;
    }
    return true;
  }

  // The cells' triangle lists. Each triangle must sit exactly in the cells of its range, once per
  // cell: then a query (and a later update_triangles, which unbins by range) sees the same table
  // as the saved one.
  static bool read_cells(CacheReader& in, CylindricalTable& table) {
    const std::size_t num_triangles = table.triangles_.size();
    // num_r and num_z fit in 31 bits each, so the product cannot overflow.
    const std::size_t num_cells = in.count(4);
    if (!in.ok() || num_cells != static_cast<std::size_t>(table.num_r_ * table.num_z_)) return false;
    std::vector<std::uint32_t> sizes(num_cells);
    std::uint64_t total = 0;
    for (std::uint32_t& size : sizes) {
      size = in.u32();
      total += size;
    }
    if (!in.can_hold(total, 4)) return false;
    std::vector<std::uint64_t> seen(num_triangles, 0);
    std::vector<std::size_t> last_cell(num_triangles, std::numeric_limits<std::size_t>::max());
    table.cells_.resize(num_cells);
    for (std::size_t c = 0; c < num_cells; ++c) {
      const long long iz = static_cast<long long>(c) / table.num_r_;
      const long long ir = static_cast<long long>(c) % table.num_r_;
      auto& cell = table.cells_[c];
      cell.resize(sizes[c]);
      for (std::int32_t& t : cell) {
        t = in.i32();
        if (t < 0 || static_cast<std::size_t>(t) >= num_triangles) return false;
        const auto ti = static_cast<std::size_t>(t);
        const CylindricalTable::CellRange& range = table.ranges_[ti];
        if (ir < range.r0 || ir > range.r1 || iz < range.z0 || iz > range.z1) return false;
        if (last_cell[ti] == c) return false;
        last_cell[ti] = c;
        ++seen[ti];
      }
    }
    for (std::size_t t = 0; t < num_triangles; ++t) {
      const CylindricalTable::CellRange& range = table.ranges_[t];
      const auto area = range.r1 < range.r0 ? 0ull
                                            : static_cast<std::uint64_t>((range.r1 - range.r0 + 1) *
                                                                         (range.z1 - range.z0 + 1));
      if (seen[t] != area) return false;
    }
    return true;
  }

  // The overflow list: exactly the triangles whose range says they overflow, each once.
  static bool read_overflow(CacheReader& in, CylindricalTable& table) {
    const std::size_t num_triangles = table.triangles_.size();
    const std::size_t num_overflow = in.count(4);
    table.overflow_.resize(num_overflow);
    std::vector<bool> listed(num_triangles, false);
    for (std::int32_t& t : table.overflow_) {
      t = in.i32();
      if (t < 0 || static_cast<std::size_t>(t) >= num_triangles) return false;
      const auto ti = static_cast<std::size_t>(t);
      if (listed[ti] || !table.ranges_[ti].overflow) return false;
      listed[ti] = true;
    }
    for (std::size_t t = 0; t < num_triangles; ++t) {
      if (table.ranges_[t].overflow != listed[t]) return false;
    }
    return true;
  }

  static void write_pose_cache(const CylindricalPoseCache& cache, Writer& out) {
    out.u8(encode_status(cache.status_));
    out.string(cache.message_);
    out.i32(cache.options_.num_threads);
    out.f64(cache.options_.touching_mm);
    out.u64(cache.normals_.size());
    for (const Vec3& n : cache.normals_) out.vec3(n);
    out.u64(cache.crossing_theta_.size());
    for (std::size_t i = 0; i < cache.crossing_theta_.size(); ++i) {
      out.f64(cache.crossing_theta_[i]);
      out.i32(cache.crossing_triangle_[i]);
    }
    out.u64(cache.tracked_.size());
    for (const CylindricalPoseCache::TrackedVertex& vertex : cache.tracked_) {
      out.i32(vertex.vertex);
      out.f64(vertex.r);
      out.f64(vertex.z);
      out.f64(vertex.theta0_rad);
      out.u64(vertex.first);
      out.u64(vertex.last);
    }
  }

  static std::optional<CylindricalPoseCache> read_pose_cache(CacheReader& in) {
    CylindricalPoseCache cache;
    const std::optional<QueryStatus> status = decode_status(in.u8());
    if (!status) return std::nullopt;
    cache.status_ = *status;
    cache.message_ = in.string();
    cache.options_.num_threads = in.i32();
    cache.options_.touching_mm = in.f64();
    // Thread counts beyond any real machine would make query() try to spawn that many threads.
    constexpr int kMaxThreads = 4096;
    if (!in.ok() || std::isnan(cache.options_.touching_mm) ||
        cache.options_.num_threads > kMaxThreads) {
      return std::nullopt;
    }

    const std::size_t num_normals = in.count(3 * 8);
    cache.normals_.resize(num_normals);
    for (Vec3& n : cache.normals_) {
      n = in.vec3();
      if (!finite(n)) return std::nullopt;
    }
    const std::size_t num_crossings = in.count(8 + 4);
    cache.crossing_theta_.resize(num_crossings);
    cache.crossing_triangle_.resize(num_crossings);
    for (std::size_t i = 0; i < num_crossings; ++i) {
      cache.crossing_theta_[i] = in.f64();
      const std::int32_t t = in.i32();
      cache.crossing_triangle_[i] = t;
      // Crossing angles are in (-pi, pi] (circle_triangle_crossings); the arc index relies on it.
      if (!std::isfinite(cache.crossing_theta_[i]) || std::abs(cache.crossing_theta_[i]) > std::numbers::pi || t < 0 ||
          static_cast<std::size_t>(t) >= num_normals) {
        return std::nullopt;
      }
    }
    const std::size_t num_tracked = in.count(4 + 3 * 8 + 2 * 8);
    cache.tracked_.resize(num_tracked);
    for (CylindricalPoseCache::TrackedVertex& vertex : cache.tracked_) {
      vertex.vertex = in.i32();
      vertex.r = in.f64();
      vertex.z = in.f64();
      vertex.theta0_rad = in.f64();
      const std::uint64_t first = in.u64();
      const std::uint64_t last = in.u64();
      // A tracked vertex has at least one crossing: query() reads the nearest one's normal.
      if (!in.ok() || vertex.vertex < 0 || !std::isfinite(vertex.r) || !std::isfinite(vertex.z) ||
          !std::isfinite(vertex.theta0_rad) || first >= last || last > num_crossings) {
        return std::nullopt;
      }
      vertex.first = static_cast<std::size_t>(first);
      vertex.last = static_cast<std::size_t>(last);
    }
    if (!in.ok()) return std::nullopt;
    cache.build_index();  // derived data, not stored: rebuilt as the constructor builds it
    return cache;
  }
};

}  // namespace detail

void save_cylindrical_table(const CylindricalTable& table, const std::filesystem::path& path) {
  constexpr long long kMaxCells = std::numeric_limits<std::int32_t>::max();
  if (table.num_r_cells() > kMaxCells || table.num_z_cells() > kMaxCells) {
    throw_error("save_cylindrical_table: '", path.string(), "': grid of ", table.num_r_cells(), " x ",
                table.num_z_cells(), " cells exceeds the file format's 2^31 - 1 per direction");
  }
  Writer payload;
  detail::CylindricalCacheAccess::write_table(table, payload);
  write_file(kTableKind, payload.bytes(), path, "save_cylindrical_table");
}

std::optional<CylindricalTable> load_cylindrical_table(const std::filesystem::path& path) {
  const std::optional<std::vector<std::byte>> payload = read_payload(kTableKind, path);
  if (!payload) return std::nullopt;
  CacheReader in(*payload);
  std::optional<CylindricalTable> table = detail::CylindricalCacheAccess::read_table(in);
  // Trailing bytes mean the file is not what this version writes.
  if (!table || !in.ok() || in.remaining() != 0) return std::nullopt;
  return table;
}

void save_pose_cache(const CylindricalPoseCache& cache, const std::filesystem::path& path) {
  Writer payload;
  detail::CylindricalCacheAccess::write_pose_cache(cache, payload);
  write_file(kPoseCacheKind, payload.bytes(), path, "save_pose_cache");
}

std::optional<CylindricalPoseCache> load_pose_cache(const std::filesystem::path& path) {
  const std::optional<std::vector<std::byte>> payload = read_payload(kPoseCacheKind, path);
  if (!payload) return std::nullopt;
  CacheReader in(*payload);
  std::optional<CylindricalPoseCache> cache = detail::CylindricalCacheAccess::read_pose_cache(in);
  if (!cache || !in.ok() || in.remaining() != 0) return std::nullopt;
  return cache;
}

}  // namespace hipfai::contact
