// libFuzzer harness of the radial table cache reader (studies/radial_table_cache.h,
// load_radial_table: the tables a study keeps in its cache folder and reuses on a re-run): the
// bytes are written to a scratch file and loaded. A damaged file must give std::nullopt; a table
// it returns is checked here once more against the invariants the queries index by.
#include "fuzz_outcome.h"
#include "fuzz_scratch.h"
#include "contact/radial_table_io.h"

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = hipfai::fuzz::write_scratch_file("table.bin", hipfai::fuzz::bytes_of(data, size));
  return hipfai::fuzz::parse_or_error([&] {
    const auto table = hipfai::contact::load_radial_table(file);
    if (!table) return;
    // Every index a query follows must lie inside what it indexes (else: a finding).
    const auto cells = static_cast<std::int64_t>(table->grid.num_cells());
    const auto triangles = static_cast<std::int64_t>(table->num_triangles);
    if (static_cast<std::int64_t>(table->cells.size()) != cells) std::abort();
    for (const auto& cell : table->cells) {
      for (const std::int32_t t : cell) {
        if (t < 0 || t >= triangles) std::abort();
      }
    }
    for (const auto& list : table->triangle_cells) {
      for (const std::int32_t c : list) {
        if (c < 0 || c >= cells) std::abort();
      }
    }
  });
}
