// hipfai — an FE run's per-step table read into typed step records (see hip_fe_table.h).
#include "studies/results/hip_fe_table.h"

#include "core/csv.h"
#include "core/error.h"
#include "core/numbers.h"
#include "studies/results/table_number.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

namespace hipfai::studies {
namespace {

using hipfai::kNaN;

// Where a record's fields are in a row: the header read once, the rows read by index.
struct Layout {
  std::size_t width = 0;  // cells per row
  std::size_t status = 0, wall_time_s = 0, dofs = 0;
  std::array<std::size_t, kPressureStats.size()> pressure{};  // [PressureStat]
  // [VonMisesStat][FeTissue]; empty for a tissue the run does not have.
  std::array<std::array<std::optional<std::size_t>, kFeTissues.size()>, kVonMisesStats.size()> von_mises{};
  std::vector<FeTissue> tissues;  // those the run has, in column order
};

Layout layout_of(const std::vector<std::string>& header, const std::string& source) {
  std::map<std::string, std::size_t> index;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (!index.emplace(header[c], c).second) throw_error(source, ": column '", header[c], "' appears twice");
  }
  const auto find = [&](const std::string& name) -> std::optional<std::size_t> {
    const auto it = index.find(name);
    return it == index.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  };
  const auto require = [&](const std::string& name) {
    const auto column = find(name);
    if (!column) throw_error(source, ": no column '", name, "' (the per-step table of an FE run)");
    return *column;
  };
  Layout layout;
  layout.width = header.size();
  layout.status = require("status");
  layout.wall_time_s = require("wall_time_s");
  layout.dofs = require("dofs");
  for (const PressureStat stat : kPressureStats) {
    layout.pressure[static_cast<std::size_t>(stat)] = require(fe_csv_column(stat));
  }
  // A tissue is in the run when it has any von Mises column; then it must have them all.
  std::vector<std::pair<std::size_t, FeTissue>> first_column;
  for (const FeTissue tissue : kFeTissues) {
    const bool present = std::any_of(kVonMisesStats.begin(), kVonMisesStats.end(),
                                     [&](VonMisesStat stat) { return find(fe_csv_column(stat, tissue)).has_value(); });
    if (!present) continue;
    std::size_t first = header.size();
    for (const VonMisesStat stat : kVonMisesStats) {
      const std::size_t column = require(fe_csv_column(stat, tissue));
      layout.von_mises[static_cast<std::size_t>(stat)][static_cast<std::size_t>(tissue)] = column;
      first = std::min(first, column);
    }
    first_column.emplace_back(first, tissue);
  }
  std::sort(first_column.begin(), first_column.end());
  for (const auto& [column, tissue] : first_column) layout.tissues.push_back(tissue);
  return layout;
}

FeStepRecord record_of(const std::vector<std::string>& cells, const Layout& layout, const std::string& where) {
  FeStepRecord step;
  const double status = table_number(cells[layout.status]);
  if (!(std::isfinite(status) && status == std::floor(status) && std::abs(status) <= 1e9)) {
    throw_error(where, ": status '", cells[layout.status], "' is not a whole number");
  }
  step.status = static_cast<int>(status);
  step.wall_time_s = table_number(cells[layout.wall_time_s]);
  step.dofs = table_number(cells[layout.dofs]);
  for (std::size_t s = 0; s < kPressureStats.size(); ++s) {
    step.pressure_mpa[s] = table_number(cells[layout.pressure[s]]);
  }
  for (std::size_t s = 0; s < kVonMisesStats.size(); ++s) {
    for (std::size_t t = 0; t < kFeTissues.size(); ++t) {
      const auto& column = layout.von_mises[s][t];
      step.von_mises_mpa[s][t] = column ? table_number(cells[*column]) : kNaN;
    }
  }
  return step;
}

}  // namespace

HipFeTable parse_hip_fe_csv(std::istream& in, const std::string& source) {
  std::string line;
  if (!std::getline(in, line) || line.empty()) throw_error(source, ": empty FE table");
  const Layout layout = layout_of(split_csv_line(line), source);
  HipFeTable table;
  table.tissues = layout.tissues;
  std::size_t line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() != layout.width) {
      throw_error(source, ":", line_number, ": ", cells.size(), " cells, the header has ", layout.width);
    }
    table.steps.push_back(record_of(cells, layout, source + ":" + std::to_string(line_number)));
  }
  return table;
}

HipFeTable read_hip_fe_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw_error(file.string(), ": cannot open the FE table");
  return parse_hip_fe_csv(in, file.string());
}

}  // namespace hipfai::studies
