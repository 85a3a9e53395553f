#include "studies/hip_fe_table.h"

#include "core/csv.h"
#include "core/error.h"

#include <fstream>
#include <limits>

namespace hipfai::studies {

const std::vector<double>& HipFeTable::column(const std::string& name) const {
  const auto it = values.find(name);
  if (it == values.end()) throw_error("FE table: no column '", name, "'");
  return it->second;
}

HipFeTable read_hip_fe_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw_error(file.string(), ": cannot open the FE table");
  std::string line;
  if (!std::getline(in, line) || line.empty()) throw_error(file.string(), ": empty FE table");
  HipFeTable table;
  table.columns = split_csv_line(line);
  for (const std::string& name : table.columns) table.values[name];
  std::size_t line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() != table.columns.size()) {
      throw_error(file.string(), ":", line_number, ": ", cells.size(), " cells, the header has ",
                  table.columns.size());
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      double value = std::numeric_limits<double>::quiet_NaN();
      try {
        std::size_t used = 0;
        value = std::stod(cells[c], &used);
        if (used != cells[c].size()) value = std::numeric_limits<double>::quiet_NaN();
      } catch (const std::exception&) {
      }
      table.values[table.columns[c]].push_back(value);
    }
    ++table.rows;
  }
  return table;
}

}  // namespace hipfai::studies
