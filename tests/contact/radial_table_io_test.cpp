#include "contact/radial_table_io.h"

#include "contact/radial_segmenting.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>

namespace hipfai::contact {
namespace {

// A table read back from disk must answer every query exactly like the table it was saved from.
TEST(RadialTableCache, RoundTripAnswersIdentically) {
  // A socket: spherical shell 10..12 mm (inner surface wound inward), and a ball slightly too big.
  auto inner = geometry::make_octasphere(geometry::Vec3(0.5, 0, 0), 10.0, 4);
  for (auto& t : inner.triangles) std::swap(t[1], t[2]);
  const auto outer = geometry::make_octasphere(geometry::Vec3(0.5, 0, 0), 12.0, 4);
  const auto socket = geometry::merge_meshes({&inner, &outer});
  auto ball = geometry::make_octasphere(geometry::Vec3(0, 0.3, 0.2), 10.2, 4);
  for (const auto mapping : {contact::RadialMapping::kSpherical, contact::RadialMapping::kCartesian,
                             contact::RadialMapping::kCube}) {
    contact::RadialTableOptions options;
    options.mapping = mapping;
    options.table_size = 1500;
    const auto table = contact::build_radial_table(socket, geometry::Vec3::Zero(), options);
    const auto path = std::filesystem::temp_directory_path() / "hipfai_radial_table.bin";
    save_radial_table(table, path);
    const auto loaded = load_radial_table(path);
    ASSERT_TRUE(loaded.has_value());
    EXPECT_EQ(loaded->num_entries(), table.num_entries());
    const auto a = contact::radial_segmenting(table, socket, ball, {});
    const auto b = contact::radial_segmenting(*loaded, socket, ball, {});
    ASSERT_GT(a.pairs.size(), 0u);
    ASSERT_EQ(a.pairs.size(), b.pairs.size());
    for (std::size_t i = 0; i < a.pairs.size(); ++i) {
      EXPECT_EQ(a.pairs[i].mobile_vertex, b.pairs[i].mobile_vertex);
      EXPECT_EQ(a.pairs[i].fixed_triangle, b.pairs[i].fixed_triangle);
      EXPECT_EQ(a.pairs[i].depth_mm, b.pairs[i].depth_mm);
    }
  }
}

TEST(RadialTableCache, DamagedFileIsRejectedNotTrusted) {
  const auto path = std::filesystem::temp_directory_path() / "hipfai_radial_table_bad.bin";
  const auto socket = geometry::make_octasphere(geometry::Vec3::Zero(), 10.0, 2);
  save_radial_table(contact::build_radial_table(socket, geometry::Vec3::Zero(), {}), path);
  const auto size = std::filesystem::file_size(path);
  std::filesystem::resize_file(path, size / 2);
  EXPECT_FALSE(load_radial_table(path).has_value());
  std::ofstream(path) << "not a table";
  EXPECT_FALSE(load_radial_table(path).has_value());
  EXPECT_FALSE(load_radial_table(path.string() + ".missing").has_value());
}

// A small table written field by field (save_radial_table stores what it is given, sound or not).
contact::RadialTable small_table() {
  contact::RadialTable table;
  table.grid.mapping = contact::RadialMapping::kSpherical;
  table.grid.faces = 1;
  table.grid.dimension = 2;
  table.num_triangles = 3;
  table.cells = {{0}, {0, 1}, {}, {}};
  table.triangle_cells = {{0, 1}, {1}, {}};
  table.always_candidates = {2};
  table.is_always = {0, 0, 1};
  return table;
}

// Files with every count and size in order but contents a query would trip over: each is refused.
TEST(RadialTableCache, TablesWhoseIndicesOrBinningDoNotHoldAreRefused) {
  const auto path = std::filesystem::temp_directory_path() / "hipfai_radial_table_crafted.bin";
  save_radial_table(small_table(), path);
  ASSERT_TRUE(load_radial_table(path).has_value());
  const auto refused = [&](const char* what, const std::function<void(contact::RadialTable&)>& damage) {
    contact::RadialTable table = small_table();
    damage(table);
    save_radial_table(table, path);
    EXPECT_FALSE(load_radial_table(path).has_value()) << what;
  };
  refused("a triangle index past the end", [](auto& t) { t.cells[2] = {3}; t.triangle_cells.push_back({}); });
  refused("a negative triangle index", [](auto& t) { t.cells[3] = {-1}; });
  refused("a cell index past the grid", [](auto& t) { t.triangle_cells[1] = {1, 4}; });
  refused("the two binnings disagree", [](auto& t) { t.cells[2] = {1}; });
  refused("an always-candidate not flagged", [](auto& t) { t.is_always = {0, 0, 0}; });
  refused("an always-candidate out of range", [](auto& t) { t.always_candidates = {7}; });
  refused("a grid that is not the mapping's", [](auto& t) { t.grid.faces = 6; });
  refused("a centre that is not finite", [](auto& t) { t.centre.x() = std::nan(""); });
  // A count that claims more entries than the file holds (the cell list of cell 0: 2^40).
  save_radial_table(small_table(), path);
  {
    std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
    file.seekp(static_cast<std::streamoff>(sizeof("HIPFAI-RADIAL-TABLE v2") + 3 * 4 + 3 * 8 + 2 * 8));
    const std::uint64_t huge = std::uint64_t{1} << 40;
    file.write(reinterpret_cast<const char*>(&huge), sizeof huge);
  }
  EXPECT_FALSE(load_radial_table(path).has_value());
  // Bytes after the last field.
  save_radial_table(small_table(), path);
  std::ofstream(path, std::ios::binary | std::ios::app) << 'x';
  EXPECT_FALSE(load_radial_table(path).has_value());
  std::filesystem::remove(path);
}

TEST(RadialTableCache, OlderVersionIsRejectedAndRebuiltInPlace) {
  // A v1 file has the v2 layout (only its near-centre-plane triangles sat in the always-candidate
  // list), so it would load without complaint if the header were not checked: patch a fresh file's
  // header back to v1 and expect the loader to refuse it.
  const auto path = std::filesystem::temp_directory_path() / "hipfai_radial_table_v1.bin";
  const auto socket = geometry::make_octasphere(geometry::Vec3(0.5, 0, 0), 10.0, 3);
  const auto table = contact::build_radial_table(socket, geometry::Vec3::Zero(), {});
  save_radial_table(table, path);
  const auto fresh = load_radial_table(path);
  ASSERT_TRUE(fresh.has_value());
  EXPECT_EQ(fresh->num_entries(), table.num_entries());
  EXPECT_EQ(fresh->always_candidates, table.always_candidates);
  EXPECT_EQ(fresh->cells, table.cells);

  constexpr char kOldMagic[] = "HIPFAI-RADIAL-TABLE v1";
  {
    std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
    ASSERT_TRUE(file.good());
    char header[sizeof kOldMagic];
    ASSERT_TRUE(file.read(header, sizeof header));
    ASSERT_EQ(std::string(header, sizeof header - 1), std::string("HIPFAI-RADIAL-TABLE v2"));
    file.seekp(0);
    file.write(kOldMagic, sizeof kOldMagic);
  }
  EXPECT_FALSE(load_radial_table(path).has_value());

  // The cache's answer to a refused file: build again and save at the same path, which loads.
  save_radial_table(table, path);
  const auto rebuilt = load_radial_table(path);
  ASSERT_TRUE(rebuilt.has_value());
  EXPECT_EQ(rebuilt->cells, table.cells);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hipfai::contact
