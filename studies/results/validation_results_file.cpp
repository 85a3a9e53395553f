#include "studies/results/validation_results_file.h"

#include "core/csv.h"
#include "core/error.h"
#include "core/numbers.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>

namespace hipfai::studies {

namespace {

using hipfai::kNaN;

double parse_cell(const std::string& text, const std::filesystem::path& file, std::size_t line, bool allow_empty) {
  if (text.empty()) {
    if (allow_empty) return kNaN;
    throw_error(file.string(), ":", line, ": empty cell");
  }
  std::size_t used = 0;
  double value = kNaN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size()) throw_error(file.string(), ":", line, ": '", text, "' is not a number");
  return value;
}

// A whole number of at least 0 that fits an int (a missing or empty cell is 0).
int count(const std::map<std::string, std::string>& cell, const std::string& name,
          const std::filesystem::path& file, std::size_t line) {
  const auto it = cell.find(name);
  if (it == cell.end() || it->second.empty()) return 0;
  const double value = parse_cell(it->second, file, line, false);
  if (!(value >= 0.0 && value <= std::numeric_limits<int>::max()) || value != std::floor(value)) {
    throw_error(file.string(), ":", line, ": ", name, " '", it->second, "' is not a count");
  }
  return static_cast<int>(value);
}

}  // namespace

const std::vector<double>& ValidationHipSeries::depth(const std::string& kind) const {
  if (kind == "curvilinear") return curvilinear_mm;
  if (kind == "radial") return radial_mm;
  throw_error("validation: unknown depth kind '", kind, "'");
}

ValidationData read_validation_results(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "steps.csv";
  std::ifstream in(file);
  if (!in) throw_error(file.string(), ": cannot open (run `hipfai study validate --out ", dir.string(), "` first)");
  std::string line;
  if (!std::getline(in, line)) throw_error(file.string(), ": empty");
  const std::vector<std::string> header = split_csv_line(line);
  const std::vector<std::string> required{"ce_deg", "alpha_deg", "step", "angle_deg", "max_curvilinear_mm",
                                          "max_radial_mm"};
  if (header.size() < required.size() || !std::equal(required.begin(), required.end(), header.begin())) {
    throw_error(file.string(), ":1: the header must begin with ce_deg,alpha_deg,step,angle_deg,"
                "max_curvilinear_mm,max_radial_mm");
  }
  ValidationData data;
  for (std::size_t c = required.size(); c < header.size(); ++c) {
    if (header[c].size() < 4 || header[c].substr(header[c].size() - 4) != "_mpa") {
      throw_error(file.string(), ":1: column '", header[c], "' is not an FE measure (names end in _mpa)");
    }
    data.measures.push_back(header[c]);
  }
  std::size_t number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() != header.size()) {
      throw_error(file.string(), ":", number, ": ", cells.size(), " cells, the header has ", header.size());
    }
    const double ce = parse_cell(cells[0], file, number, false), alpha = parse_cell(cells[1], file, number, false);
    if (data.hips.empty() || data.hips.back().ce_deg != ce || data.hips.back().alpha_deg != alpha) {
      ValidationHipSeries hip;
      hip.ce_deg = ce;
      hip.alpha_deg = alpha;
      hip.fe.assign(data.measures.size(), {});
      data.hips.push_back(std::move(hip));
    }
    ValidationHipSeries& hip = data.hips.back();
    hip.angle_deg.push_back(parse_cell(cells[3], file, number, false));
    hip.curvilinear_mm.push_back(parse_cell(cells[4], file, number, false));
    hip.radial_mm.push_back(parse_cell(cells[5], file, number, false));
    for (std::size_t m = 0; m < data.measures.size(); ++m) {
      hip.fe[m].push_back(parse_cell(cells[required.size() + m], file, number, true));
    }
  }
  if (data.hips.empty()) throw_error(file.string(), ": no rows");

  const std::filesystem::path timings = dir / "timings.csv";
  std::ifstream tin(timings);
  if (tin && std::getline(tin, line)) {
    const std::vector<std::string> columns = split_csv_line(line);
    std::size_t tnumber = 1;
    while (std::getline(tin, line)) {
      ++tnumber;
      if (line.empty()) continue;
      const std::vector<std::string> cells = split_csv_line(line);
      if (cells.size() != columns.size()) {
        throw_error(timings.string(), ":", tnumber, ": ", cells.size(), " cells, the header has ", columns.size());
      }
      std::map<std::string, std::string> cell;
      for (std::size_t c = 0; c < cells.size(); ++c) cell[columns[c]] = cells[c];
      auto num = [&](const std::string& name) {
        return cell.count(name) ? parse_cell(cell[name], timings, tnumber, true) : kNaN;
      };
      ValidationHipTimingRow row;
      row.ce_deg = num("ce_deg");
      row.alpha_deg = num("alpha_deg");
      row.edge_mm = num("edge_mm");
      row.steps = count(cell, "steps", timings, tnumber);
      row.fe_level = cell["fe_level"];
      row.generate_s = num("generate_s");
      row.penetration_tables_ms = num("penetration_tables_ms");
      row.penetration_query_ms = num("penetration_query_ms");
      row.fe_s = num("fe_s");
      row.fe_step_s = num("fe_step_s");
      row.fe_reused = num("fe_reused") == 1.0;
      row.fe_steps_failed = count(cell, "fe_steps_failed", timings, tnumber);
      row.fe_dofs = num("fe_dofs");
      data.timings.push_back(row);
    }
  }
  return data;
}

}  // namespace hipfai::studies
