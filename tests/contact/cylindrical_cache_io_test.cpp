// Save/load of the cylindrical artefacts: a loaded table / pose cache must answer bit-for-bit
// like the saved one (random scenes, deformed tables, the real CT femur and pelvis), and damaged
// files (missing, truncated, other version or kind, flipped bytes, garbage, crafted counts) must
// give std::nullopt without crashing or allocating what the file cannot hold.
#include "contact/cylindrical_cache_io.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "core/numbers.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <unistd.h>
#include <vector>

namespace hipfai::contact {
namespace {

namespace fs = std::filesystem;
using geometry::TriMesh;
using test_shapes::random_shape;
using test_shapes::random_unit;

using hipfai::kPi;
constexpr std::size_t kHeaderBytes = 36;  // magic 12, kind 4, version 4, size 8, checksum 8

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("hipfai_cyl_cache_io_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

std::vector<char> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const fs::path& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void put_u64(std::vector<char>& bytes, std::size_t at, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes[at + static_cast<std::size_t>(i)] = static_cast<char>(value >> (8 * i));
}

// Recomputes the header's checksum after the payload was edited, so that only the structural
// checks stand between the edited file and the queries.
void fix_checksum(std::vector<char>& bytes) {
  std::span<const std::byte> payload(reinterpret_cast<const std::byte*>(bytes.data()) + kHeaderBytes,
                                     bytes.size() - kHeaderBytes);
  put_u64(bytes, 28, cylindrical_cache_checksum(payload));
}

// A file with a valid header (kind, version, size, checksum) around `payload`.
std::vector<char> crafted_file(const std::string& kind, const std::vector<char>& payload) {
  std::vector<char> bytes(kHeaderBytes, 0);
  const std::string magic = "HIPFAI-CACHE" + kind;
  std::copy(magic.begin(), magic.end(), bytes.begin());
  bytes[16] = static_cast<char>(kCylindricalCacheVersion);
  put_u64(bytes, 20, payload.size());
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  fix_checksum(bytes);
  return bytes;
}

void append_u64(std::vector<char>& bytes, std::uint64_t value) {
  bytes.resize(bytes.size() + 8);
  put_u64(bytes, bytes.size() - 8, value);
}

// Bit equality (not a tolerance): the file stores doubles as their IEEE bits and the loaded
// object runs the same code on them, so any difference is a bug.
bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

void expect_identical_cached(const PenetrationResult& got, const PenetrationResult& want, const std::string& what) {
  ASSERT_EQ(got.status, want.status) << what;
  ASSERT_EQ(got.pairs.size(), want.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    const PenetrationPair& a = got.pairs[i];
    const PenetrationPair& b = want.pairs[i];
    ASSERT_EQ(a.mobile_vertex, b.mobile_vertex) << what << " pair " << i;
    ASSERT_EQ(a.fixed_triangle, b.fixed_triangle) << what << " pair " << i;
    ASSERT_TRUE(same_bits(a.depth_mm, b.depth_mm)) << what << " pair " << i;
    ASSERT_TRUE(same_bits(a.angle_deg, b.angle_deg)) << what << " pair " << i;
  }
}

void expect_same_vec(const Vec3& a, const Vec3& b, const std::string& what) {
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(same_bits(a[i], b[i])) << what;
}

// The last distance between `inside` (touching) and `outside` at which distance_may_touch is
// still true, found by bisection on the bit patterns of non-negative doubles (ordered like the
// values), so the result is exact to the last bit.
double touch_edge(const CylindricalTable& table, double inside, double outside) {
  std::uint64_t in = std::bit_cast<std::uint64_t>(inside), out = std::bit_cast<std::uint64_t>(outside);
  if (table.distance_may_touch(outside)) return outside;
  while (in + 1 != out && out + 1 != in) {
    const std::uint64_t mid = in < out ? in + (out - in) / 2 : out + (in - out) / 2;
    (table.distance_may_touch(std::bit_cast<double>(mid)) ? in : out) = mid;
  }
  return std::bit_cast<double>(in);
}

// Everything the public interface shows of a table.
void expect_same_table(const CylindricalTable& got, const CylindricalTable& want) {
  ASSERT_EQ(got.status(), want.status());
  ASSERT_EQ(got.message(), want.message());
  expect_same_vec(got.frame().centre, want.frame().centre, "centre");
  expect_same_vec(got.frame().axis, want.frame().axis, "axis");
  expect_same_vec(got.frame().e1, want.frame().e1, "e1");
  expect_same_vec(got.frame().e2, want.frame().e2, "e2");
  ASSERT_EQ(got.num_r_cells(), want.num_r_cells());
  ASSERT_EQ(got.num_z_cells(), want.num_z_cells());
  ASSERT_TRUE(same_bits(got.resolution_r_mm(), want.resolution_r_mm()));
  ASSERT_TRUE(same_bits(got.resolution_z_mm(), want.resolution_z_mm()));
  ASSERT_TRUE(same_bits(got.r_lo_mm(), want.r_lo_mm()));
  ASSERT_TRUE(same_bits(got.z_lo_mm(), want.z_lo_mm()));
  ASSERT_EQ(got.neighbour_cells(), want.neighbour_cells());
  ASSERT_EQ(got.num_overflow_triangles(), want.num_overflow_triangles());
  ASSERT_EQ(got.num_vertices(), want.num_vertices());
  ASSERT_EQ(got.num_triangles(), want.num_triangles());
  for (std::size_t v = 0; v < got.num_vertices(); ++v) {
    expect_same_vec(got.local_vertex(static_cast<std::int32_t>(v)), want.local_vertex(static_cast<std::int32_t>(v)),
                    "vertex");
  }
  for (std::size_t t = 0; t < got.num_triangles(); ++t) {
    const auto id = static_cast<std::int32_t>(t);
    ASSERT_EQ(got.triangle(id), want.triangle(id));
    expect_same_vec(got.local_normal(id), want.local_normal(id), "normal");
  }
  for (long long iz = 0; iz < got.num_z_cells(); ++iz) {
    for (long long ir = 0; ir < got.num_r_cells(); ++ir) ASSERT_EQ(got.cell(iz, ir), want.cell(iz, ir));
  }
  // The L filter's bounds are private: find both edges of distance_may_touch to the last bit.
  if (want.num_vertices() > 0) {
    const double inside = want.local_vertex(0).norm();  // l_min <= |vertex| <= l_max
    ASSERT_TRUE(want.distance_may_touch(inside));
    ASSERT_TRUE(same_bits(touch_edge(got, inside, 0.0), touch_edge(want, inside, 0.0)));
    ASSERT_TRUE(same_bits(touch_edge(got, inside, 1e300), touch_edge(want, inside, 1e300)));
  }
}

void expect_same_pose_cache(const CylindricalPoseCache& got, const CylindricalPoseCache& want) {
  ASSERT_EQ(got.status(), want.status());
  ASSERT_TRUE(same_bits(got.touching_mm(), want.touching_mm()));
  ASSERT_EQ(got.tracked().size(), want.tracked().size());
  for (std::size_t i = 0; i < got.tracked().size(); ++i) {
    const auto& a = got.tracked()[i];
    const auto& b = want.tracked()[i];
    ASSERT_EQ(a.vertex, b.vertex);
    ASSERT_TRUE(same_bits(a.r, b.r) && same_bits(a.z, b.z) && same_bits(a.theta0_rad, b.theta0_rad));
    ASSERT_EQ(a.first, b.first);
    ASSERT_EQ(a.last, b.last);
  }
  ASSERT_EQ(got.num_crossings(), want.num_crossings());
  for (std::size_t i = 0; i < got.num_crossings(); ++i) {
    ASSERT_TRUE(same_bits(got.crossing_theta_rad(i), want.crossing_theta_rad(i)));
    ASSERT_EQ(got.crossing_triangle(i), want.crossing_triangle(i));
  }
}

// Moves every 5th vertex by up to `displacement_mm`; returns the triangles that changed.
std::vector<std::int32_t> deform_some(TriMesh& mesh, std::mt19937& rng, double displacement_mm) {
  std::set<std::int32_t> moved;
  for (std::size_t v = 0; v < mesh.vertices.size(); v += 5) {
    mesh.vertices[v] += random_unit(rng) * displacement_mm;
    moved.insert(static_cast<std::int32_t>(v));
  }
  std::vector<std::int32_t> changed;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::int32_t v : mesh.triangles[t]) {
      if (moved.count(v)) {
        changed.push_back(static_cast<std::int32_t>(t));
        break;
      }
    }
  }
  return changed;
}

TriMesh posed(const TriMesh& mobile, const CylindricalTable& table, double angle_deg) {
  TriMesh result = mobile;
  geometry::rotate_about_axis(result, table.frame().centre, table.frame().axis, angle_deg * kPi / 180.0);
  return result;
}

TEST(CylindricalCacheIo, TableAndPoseCacheRoundTripOnRandomScenes) {
  const TempDir dir;
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t pairs_seen = 0, overflow_seen = 0;
  for (int trial = 0; trial < 16; ++trial) {
    TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh mobile = random_shape(rng, (trial / 3) % 3);
    const Vec3 centre(10 * u(rng) - 5, 10 * u(rng) - 5, 10 * u(rng) - 5);
    const Vec3 axis = random_unit(rng) * (0.5 + 3 * u(rng));
    CylindricalTableOptions options;
    options.neighbour_cells = trial % 4 == 3 ? 1 : 0;
    // Variants: restricted to the mobile mesh or not; deformed (with overflow) or not.
    const bool restricted = trial % 2 == 0;
    CylindricalTable table =
        CylindricalTable::build(fixed, centre, axis, options, restricted ? &mobile : nullptr);
    if (trial % 4 == 1) update_triangles(table, fixed, deform_some(fixed, rng, 20.0));
    overflow_seen += table.num_overflow_triangles();
    const std::string what = "trial " + std::to_string(trial);

    const fs::path table_path = dir / ("table" + std::to_string(trial) + ".bin");
    save_cylindrical_table(table, table_path);
    for (const auto& entry : fs::directory_iterator(table_path.parent_path())) {
      EXPECT_NE(entry.path().extension(), ".partial") << what;
    }
    std::optional<CylindricalTable> loaded = load_cylindrical_table(table_path);
    ASSERT_TRUE(loaded.has_value()) << what;
    expect_same_table(*loaded, table);
    for (int pose = 0; pose < 4; ++pose) {
      const TriMesh moved = posed(mobile, table, 360 * u(rng) - 180);
      const PenetrationResult want = cylindrical_segmenting(table, moved);
      expect_identical_cached(cylindrical_segmenting(*loaded, moved), want, what + " table query");
      pairs_seen += want.pairs.size();
    }

    const CylindricalPoseCache cache(table, mobile);
    const fs::path cache_path = dir / ("cache" + std::to_string(trial) + ".bin");
    save_pose_cache(cache, cache_path);
    const std::optional<CylindricalPoseCache> loaded_cache = load_pose_cache(cache_path);
    ASSERT_TRUE(loaded_cache.has_value()) << what;
    expect_same_pose_cache(*loaded_cache, cache);
    // A pose cache pre-processed from the loaded table equals the one from the original.
    expect_same_pose_cache(CylindricalPoseCache(*loaded, mobile), cache);
    for (int pose = 0; pose < 6; ++pose) {
      const double angle_deg = 360 * u(rng) - 180;
      expect_identical_cached(loaded_cache->query(angle_deg), cache.query(angle_deg), what + " pose cache");
    }

    // The private bookkeeping (cell ranges, overflow flags, pad) came back too: updating the
    // loaded table gives the same table as updating the original.
    TriMesh deformed = fixed;
    const std::vector<std::int32_t> changed = deform_some(deformed, rng, 6.0);
    update_triangles(table, deformed, changed);
    update_triangles(*loaded, deformed, changed);
    expect_same_table(*loaded, table);
    expect_identical_cached(cylindrical_segmenting(*loaded, mobile), cylindrical_segmenting(table, mobile),
                     what + " after update");
  }
  EXPECT_GT(pairs_seen, 100u);   // the scenes really collide
  EXPECT_GT(overflow_seen, 0u);  // and the overflow list was exercised
}

TEST(CylindricalCacheIo, NoOverlapAndInvalidTablesRoundTrip) {
  const TempDir dir;
  const TriMesh fixed = geometry::make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1), 2);
  TriMesh far = fixed;
  for (Vec3& p : far.vertices) p += Vec3(0, 0, 100);  // z ranges disjoint about the z axis
  const CylindricalTable no_overlap = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::UnitZ(), {}, &far);
  ASSERT_EQ(no_overlap.status(), QueryStatus::kNoOverlap);
  const CylindricalTable invalid = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::Zero());
  ASSERT_EQ(invalid.status(), QueryStatus::kInvalidInput);
  for (const CylindricalTable* table : {&no_overlap, &invalid}) {
    save_cylindrical_table(*table, dir / "t.bin");
    const std::optional<CylindricalTable> loaded = load_cylindrical_table(dir / "t.bin");
    ASSERT_TRUE(loaded.has_value());
    expect_same_table(*loaded, *table);
    const CylindricalPoseCache cache(*table, far);
    save_pose_cache(cache, dir / "c.bin");
    const std::optional<CylindricalPoseCache> loaded_cache = load_pose_cache(dir / "c.bin");
    ASSERT_TRUE(loaded_cache.has_value());
    const PenetrationResult want = cache.query(10.0);
    const PenetrationResult got = loaded_cache->query(10.0);
    expect_identical_cached(got, want, "status round trip");
    EXPECT_EQ(got.message, want.message);
  }
}

TEST(CylindricalCacheIo, RealFemurAgainstPelvisRoundTrip) {
  const TempDir dir;
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58);  // hip.json hjc_mm
  // Subsample of the femur (every 7th vertex) keeps the test fast; the pelvis table is complete.
  TriMesh femur_points;
  for (std::size_t v = 0; v < femur.vertices.size(); v += 7) femur_points.vertices.push_back(femur.vertices[v]);
  std::size_t penetrating = 0;
  for (const Vec3& axis : {Vec3(0, 1, 0), Vec3(0, 0, 1)}) {
    const auto start = std::chrono::steady_clock::now();
    const CylindricalTable table = CylindricalTable::build(pelvis, hjc, axis, {}, &femur_points);
    const CylindricalPoseCache cache(table, femur_points);
    const auto built = std::chrono::steady_clock::now();
    save_cylindrical_table(table, dir / "pelvis.cyl");
    save_pose_cache(cache, dir / "femur.pose");
    const auto saved = std::chrono::steady_clock::now();
    const std::optional<CylindricalTable> loaded = load_cylindrical_table(dir / "pelvis.cyl");
    const std::optional<CylindricalPoseCache> loaded_cache = load_pose_cache(dir / "femur.pose");
    const auto loaded_at = std::chrono::steady_clock::now();
    // Printed, never asserted: what the on-disk cache saves over a rebuild.
    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    std::cout << "[ timing ] axis (" << axis.transpose() << "): build table + pose cache "
              << ms(start, built) << " ms, save " << ms(built, saved) << " ms, load "
              << ms(saved, loaded_at) << " ms; files " << fs::file_size(dir / "pelvis.cyl") / 1024
              << " KiB + " << fs::file_size(dir / "femur.pose") / 1024 << " KiB\n";
    ASSERT_TRUE(loaded.has_value());
    ASSERT_TRUE(loaded_cache.has_value());
    expect_same_table(*loaded, table);
    expect_same_pose_cache(*loaded_cache, cache);
    for (double angle_deg = -60.0; angle_deg <= 60.0; angle_deg += 20.0) {
      const PenetrationResult want = cache.query(angle_deg);
      expect_identical_cached(loaded_cache->query(angle_deg), want, "pose cache");
      const TriMesh moved = posed(femur_points, table, angle_deg);
      expect_identical_cached(cylindrical_segmenting(*loaded, moved), cylindrical_segmenting(table, moved), "table");
      penetrating += want.pairs.size();
    }
  }
  EXPECT_GT(penetrating, 0u);  // the sweep really reaches impingement
}

// A small table and pose cache file to damage.
struct SmallFiles {
  CylindricalTable table;
  CylindricalPoseCache cache;
  TriMesh mobile;
  std::vector<char> table_bytes, cache_bytes;
};

SmallFiles small_files(const TempDir& dir) {
  std::mt19937 rng(5);
  SmallFiles files;
  const TriMesh fixed = random_shape(rng, 0);
  files.mobile = random_shape(rng, 1);
  files.table = CylindricalTable::build(fixed, Vec3(1, 0, 0), random_unit(rng), {}, &files.mobile);
  files.cache = CylindricalPoseCache(files.table, files.mobile);
  save_cylindrical_table(files.table, dir / "small.cyl");
  save_pose_cache(files.cache, dir / "small.pose");
  files.table_bytes = read_bytes(dir / "small.cyl");
  files.cache_bytes = read_bytes(dir / "small.pose");
  return files;
}

TEST(CylindricalCacheIo, MissingTruncatedOtherVersionAndOtherKindRejected) {
  const TempDir dir;
  const SmallFiles files = small_files(dir);
  ASSERT_GT(files.cache.num_crossings(), 0u);
  EXPECT_FALSE(load_cylindrical_table(dir / "missing.cyl").has_value());
  EXPECT_FALSE(load_pose_cache(dir / "missing.pose").has_value());
  EXPECT_FALSE(load_cylindrical_table(dir / "").has_value());  // a directory
  // Every prefix near the header, then a spread of lengths up to one byte short.
  for (const auto* bytes : {&files.table_bytes, &files.cache_bytes}) {
    const bool is_table = bytes == &files.table_bytes;
    std::vector<std::size_t> lengths;
    for (std::size_t n = 0; n < kHeaderBytes + 64; ++n) lengths.push_back(n);
    for (std::size_t n = kHeaderBytes + 64; n < bytes->size(); n += 997) lengths.push_back(n);
    lengths.push_back(bytes->size() - 1);
    for (std::size_t n : lengths) {
      write_bytes(dir / "cut.bin", std::vector<char>(bytes->begin(), bytes->begin() + static_cast<long>(n)));
      const bool loaded = is_table ? load_cylindrical_table(dir / "cut.bin").has_value()
                                   : load_pose_cache(dir / "cut.bin").has_value();
      ASSERT_FALSE(loaded) << "truncated to " << n << " bytes";
    }
    // The untruncated copy written the same way does load (the writer above is not at fault).
    write_bytes(dir / "cut.bin", *bytes);
    EXPECT_TRUE(is_table ? load_cylindrical_table(dir / "cut.bin").has_value()
                         : load_pose_cache(dir / "cut.bin").has_value());
    // A trailing byte (declared size no longer matches) is rejected too.
    std::vector<char> longer = *bytes;
    longer.push_back(0);
    write_bytes(dir / "long.bin", longer);
    EXPECT_FALSE(is_table ? load_cylindrical_table(dir / "long.bin").has_value()
                          : load_pose_cache(dir / "long.bin").has_value());
  }
  // Other version (the checksum covers only the payload, so only the version check can refuse).
  std::vector<char> other_version = files.table_bytes;
  other_version[16] = static_cast<char>(kCylindricalCacheVersion + 1);
  write_bytes(dir / "v.bin", other_version);
  EXPECT_FALSE(load_cylindrical_table(dir / "v.bin").has_value());
  // Other kind: each loader refuses the other's file.
  EXPECT_FALSE(load_pose_cache(dir / "small.cyl").has_value());
  EXPECT_FALSE(load_cylindrical_table(dir / "small.pose").has_value());
}

TEST(CylindricalCacheIo, CorruptedAndGarbageFilesRejected) {
  const TempDir dir;
  const SmallFiles files = small_files(dir);
  std::mt19937 rng(99);
  // Flipped bytes anywhere: the header checks or the checksum refuse every one.
  for (const auto* bytes : {&files.table_bytes, &files.cache_bytes}) {
    const bool is_table = bytes == &files.table_bytes;
    std::uniform_int_distribution<std::size_t> position(0, bytes->size() - 1);
    for (int i = 0; i < 200; ++i) {
      std::vector<char> damaged = *bytes;
      const std::size_t at = i < 36 ? static_cast<std::size_t>(i) : position(rng);
      damaged[at] = static_cast<char>(damaged[at] ^ (1 + static_cast<int>(rng() % 255)));
      write_bytes(dir / "flip.bin", damaged);
      const bool loaded = is_table ? load_cylindrical_table(dir / "flip.bin").has_value()
                                   : load_pose_cache(dir / "flip.bin").has_value();
      ASSERT_FALSE(loaded) << "byte " << at;
    }
  }
  // Garbage: random bytes, and a valid header around a random payload.
  for (int i = 0; i < 50; ++i) {
    std::vector<char> garbage(1 + rng() % 5000);
    for (char& c : garbage) c = static_cast<char>(rng());
    write_bytes(dir / "garbage.bin", garbage);
    EXPECT_FALSE(load_cylindrical_table(dir / "garbage.bin").has_value());
    EXPECT_FALSE(load_pose_cache(dir / "garbage.bin").has_value());
    write_bytes(dir / "garbage.cyl", crafted_file("CYLT", garbage));
    EXPECT_FALSE(load_cylindrical_table(dir / "garbage.cyl").has_value());
    write_bytes(dir / "garbage.pose", crafted_file("CYLP", garbage));
    EXPECT_FALSE(load_pose_cache(dir / "garbage.pose").has_value());
  }
}

TEST(CylindricalCacheIo, CraftedCountsNeverAllocateBeyondTheFile) {
  const TempDir dir;
  // Status kOk, then a message length of 2^62: without the bound, the loader would try to
  // allocate it and throw.
  std::vector<char> huge_message = {0};
  append_u64(huge_message, std::uint64_t{1} << 62);
  write_bytes(dir / "a.cyl", crafted_file("CYLT", huge_message));
  EXPECT_NO_THROW(EXPECT_FALSE(load_cylindrical_table(dir / "a.cyl").has_value()));
  write_bytes(dir / "a.pose", crafted_file("CYLP", huge_message));
  EXPECT_NO_THROW(EXPECT_FALSE(load_pose_cache(dir / "a.pose").has_value()));
  // A valid table prefix followed by a vertex count of 2^60.
  std::vector<char> huge_vertices = {0};
  append_u64(huge_vertices, 0);                                           // empty message
  for (int i = 0; i < 12; ++i) append_u64(huge_vertices, std::bit_cast<std::uint64_t>(i % 4 == 1 ? 1.0 : 0.0));
  for (int i = 0; i < 9; ++i) append_u64(huge_vertices, std::bit_cast<std::uint64_t>(1.0));
  append_u64(huge_vertices, 1);                                           // num_r
  append_u64(huge_vertices, 1);                                           // num_z
  huge_vertices.insert(huge_vertices.end(), 4, 0);                        // neighbour cells
  append_u64(huge_vertices, std::uint64_t{1} << 60);
  write_bytes(dir / "b.cyl", crafted_file("CYLT", huge_vertices));
  EXPECT_NO_THROW(EXPECT_FALSE(load_cylindrical_table(dir / "b.cyl").has_value()));
}

TEST(CylindricalCacheIo, EditedPayloadWithValidChecksumNeverBreaksQueries) {
  // Single-byte edits with the checksum recomputed: the structural checks either refuse the file
  // or the loaded object is one whose queries stay in bounds (run under ASan to see the latter).
  const TempDir dir;
  const SmallFiles files = small_files(dir);
  std::mt19937 rng(1234);
  std::size_t rejected_tables = 0, rejected_caches = 0;
  constexpr int kEdits = 300;
  for (int i = 0; i < kEdits; ++i) {
    for (const auto* bytes : {&files.table_bytes, &files.cache_bytes}) {
      const bool is_table = bytes == &files.table_bytes;
      std::vector<char> edited = *bytes;
      std::uniform_int_distribution<std::size_t> position(kHeaderBytes, bytes->size() - 1);
      const std::size_t at = position(rng);
      edited[at] = static_cast<char>(edited[at] ^ (1 + static_cast<int>(rng() % 255)));
      fix_checksum(edited);
      write_bytes(dir / "edit.bin", edited);
      if (is_table) {
        const std::optional<CylindricalTable> table = load_cylindrical_table(dir / "edit.bin");
        if (!table) {
          ++rejected_tables;
          continue;
        }
        const PenetrationResult result = cylindrical_segmenting(*table, files.mobile);
        for (const auto& pair : result.pairs) {
          ASSERT_LT(static_cast<std::size_t>(pair.fixed_triangle), table->num_triangles());
        }
      } else {
        const std::optional<CylindricalPoseCache> cache = load_pose_cache(dir / "edit.bin");
        if (!cache) {
          ++rejected_caches;
          continue;
        }
        for (double angle_deg : {-90.0, 0.0, 45.0}) (void)cache->query(angle_deg);
      }
    }
  }
  // Most bytes are coordinates (any value is a valid table) but indices, counts and cell lists
  // are checked: some edits must be refused, and not all.
  EXPECT_GT(rejected_tables, 0u);
  EXPECT_GT(rejected_caches, 0u);
  EXPECT_LT(rejected_tables, static_cast<std::size_t>(kEdits));
}

}  // namespace
}  // namespace hipfai::contact
