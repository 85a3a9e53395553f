#include "studies/estimator_study.h"

#include "core/csv.h"
#include "core/error.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "core/text_format.h"
#include "core/version.h"
#include "geometry/hip_model.h"
#include "studies/estimator_model_file.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/pipeline/segmented_hip.h"
#include "studies/results/results_file.h"
#include "studies/results/table_number.h"
#include "studies/validation_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

namespace hipfai::studies {

namespace {

using hipfai::kNaN;

std::string hip_name(double ce, double alpha) { return parametric_hip_id(ce, alpha); }

// Edge length per hip from a validation folder's timings.csv (absent file: empty map).
std::map<std::pair<double, double>, double> read_edges(const std::filesystem::path& timings) {
  std::map<std::pair<double, double>, double> edges;
  std::ifstream in(timings);
  if (!in) return edges;
  std::string line;
  std::getline(in, line);
  const auto header = split_csv_line(line);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  const int ce = column("ce_deg"), alpha = column("alpha_deg"), edge = column("edge_mm");
  if (ce < 0 || alpha < 0 || edge < 0) return edges;
  while (std::getline(in, line)) {
    const auto cells = split_csv_line(line);
    if (static_cast<int>(cells.size()) <= std::max({ce, alpha, edge})) continue;
    edges[{table_number(cells[static_cast<std::size_t>(ce)]), table_number(cells[static_cast<std::size_t>(alpha)])}] =
        table_number(cells[static_cast<std::size_t>(edge)]);
  }
  return edges;
}

struct HipFolder {
  std::filesystem::path dir;
  geometry::HipModel model;
  double load_ms = 0;
};

std::vector<HipFolder> load_hip_folders(const std::filesystem::path& hips, const FeatureGrid& grid, bool progress) {
  if (!std::filesystem::is_directory(hips)) throw_error(hips.string(), ": no such folder of hips");
  std::vector<std::filesystem::path> dirs;
  if (std::filesystem::exists(hips / "model.json")) {
    dirs.push_back(hips);
  } else {
    for (const auto& entry : std::filesystem::directory_iterator(hips)) {
      if (!entry.is_directory() || entry.path().extension() == ".partial") continue;
      if (std::filesystem::exists(entry.path() / "model.json")) dirs.push_back(entry.path());
    }
  }
  std::sort(dirs.begin(), dirs.end());
  if (dirs.empty()) throw_error(hips.string(), ": no hip folder (with model.json) in it");
  const std::set<std::string> tissues(grid.tissues.begin(), grid.tissues.end());
  std::vector<HipFolder> folders;
  ProgressBar bar("loading hips", dirs.size(), progress);
  for (const auto& dir : dirs) {
    const auto start = std::chrono::steady_clock::now();
    HipFolder folder{dir, geometry::load_hip_model(dir, tissues), 0};
    folder.load_ms = milliseconds_since(start);
    folders.push_back(std::move(folder));
    bar.advance();
  }
  return folders;
}

bool same(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a)); }

void check_same_motion(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
  bool equal = a.size() == b.size();
  for (std::size_t k = 0; equal && k < a.size(); ++k) equal = std::abs(a[k] - b[k]) <= 1e-6;
  if (!equal) {
    throw_error(what, ": motion differs (", a.size(), " steps to ", a.empty() ? 0.0 : a.back(), " deg vs ", b.size(),
                " steps to ", b.empty() ? 0.0 : b.back(), " deg); an estimator is trained on one motion");
  }
}

// A `scripts/fem-sweep` folder: summary.csv starting "model,exit_status" and, per model that
// finished, <model>.csv (the `fem run --csv` table) and <model>.h5 (its per-step rotations).
bool is_fem_sweep_folder(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir) || std::filesystem::exists(dir / "steps.csv")) return false;
  std::ifstream in(dir / "summary.csv");
  std::string line;
  return in && std::getline(in, line) && line.rfind("model,exit_status", 0) == 0;
}

#ifdef HIPFAI_WITH_FEM
// CE and alpha from a grid model's name ("ce20_alpha40", `hipfai generate --grid`).
bool angles_of_model_name(const std::string& name, double& ce, double& alpha) {
  const std::size_t split = name.find("_alpha");
  if (name.rfind("ce", 0) != 0 || split == std::string::npos) return false;
  ce = table_number(name.substr(2, split - 2));
  alpha = table_number(name.substr(split + 6));
  return std::isfinite(ce) && std::isfinite(alpha);
}

// Each step's angle of an `fem run` (--out h5, --csv table with `rows` steps): the angle of its
// rotation (frame-free), from the HDF5.
std::vector<double> fem_run_angles(const std::filesystem::path& h5, std::size_t table_rows,
                                   const std::filesystem::path& csv) {
  std::size_t rows = 0, cols = 0;
  const std::vector<double> rotation = read_dataset(h5, "/steps/rotation", &rows, &cols);
  if (rows != table_rows || rotation.size() != 9 * rows) {
    throw_error(h5.string(), ": ", rows, " rotations for ", table_rows, " steps in ", csv.string());
  }
  std::vector<double> angles;
  for (std::size_t k = 0; k < rows; ++k) {
    const double trace = rotation[9 * k] + rotation[9 * k + 4] + rotation[9 * k + 8];
    angles.push_back(std::acos(std::clamp((trace - 1.0) / 2.0, -1.0, 1.0)) * 180.0 / std::numbers::pi);
  }
  return angles;
}

// Index of `measure` among the FE measures of `fem run` tables; throws naming `where` otherwise.
std::size_t fe_measure_index(const std::string& measure, const std::string& where) {
  const auto& measures = validation_fe_measures();
  const auto which = std::find_if(measures.begin(), measures.end(),
                                  [&](const FeMeasure& candidate) { return fe_measure_name(candidate) == measure; });
  if (which == measures.end()) {
    throw_error(where, ": ", measure, " is not one of the FE measures of `fem run` tables (",
                fe_measure_name(measures.front()), ", ...)");
  }
  return static_cast<std::size_t>(which - measures.begin());
}

FeSweep read_fem_sweep_folder(const std::filesystem::path& dir, const std::string& measure) {
  const std::size_t which = fe_measure_index(measure, dir.string());
  std::ifstream summary(dir / "summary.csv");
  std::string line;
  std::getline(summary, line);
  FeSweep sweep;
  sweep.measure = measure;
  while (std::getline(summary, line)) {
    if (line.empty()) continue;
    const std::string model = split_csv_line(line).front();
    double ce = 0, alpha = 0;
    if (!angles_of_model_name(model, ce, alpha)) {
      throw_error((dir / "summary.csv").string(), ": model '", model,
                  "': CE and alpha are read from grid names like ce20_alpha40");
    }
    const std::filesystem::path csv = dir / (model + ".csv"), h5 = dir / (model + ".h5");
    if (!std::filesystem::exists(csv)) continue;  // the model stopped before its table was written
    const HipFeTable table = read_hip_fe_csv(csv);
    const auto values = validation_fe_measures_of(table, table.steps.size(), csv);
    const std::vector<double> angles = fem_run_angles(h5, table.steps.size(), csv);
    if (sweep.hips.empty()) sweep.angle_deg = angles;
    check_same_motion(sweep.angle_deg, angles, csv.string() + " vs the sweep's other models");
    // fem-sweep tables have no penetration depths: they stay empty (impinging unknown).
    sweep.hips.push_back({ce, alpha, kNaN, values[which], {}, {}});
  }
  if (sweep.hips.empty()) throw_error(dir.string(), ": no model of the sweep has its table (<model>.csv)");
  return sweep;
}
#endif

stats::PenetrationDepths penetration_over_motion(const std::vector<double>& angle_deg, const geometry::HipModel& hip,
                                                 const std::filesystem::path& hip_dir);

// One hip and its own FE run added to (or replacing the same hip in) the model's training hips.
void add_fe_hip(EstimatorModel& model, const std::filesystem::path& dir, const std::filesystem::path& table_file,
                const std::string& measure, std::vector<std::string>* notes) {
#ifdef HIPFAI_WITH_FEM
  const HipFeTable table = read_hip_fe_csv(table_file);
  const std::filesystem::path h5 = std::filesystem::path(table_file).replace_extension(".h5");
  const std::vector<double> angles = fem_run_angles(h5, table.steps.size(), table_file);
  if (model.angle_deg.empty()) model.angle_deg = angles;
  check_same_motion(model.angle_deg, angles, table_file.string() + " vs the other training hips");
  const auto values =
      validation_fe_measures_of(table, table.steps.size(), table_file)[fe_measure_index(measure, table_file.string())];
  // Every tissue: the features read the grid's, the penetration depths the four of the thesis.
  const auto start = std::chrono::steady_clock::now();
  const geometry::HipModel hip_model = geometry::load_hip_model(dir);
  TrainingHip hip;
  hip.name = std::filesystem::path(dir).lexically_normal().filename().string();
  if (hip.name.empty()) hip.name = std::filesystem::path(dir).lexically_normal().parent_path().filename().string();
  hip.ce_deg = std::isfinite(hip_model.measured_ce_deg) ? hip_model.measured_ce_deg : hip_model.parameters.ce_deg;
  hip.alpha_deg = std::isfinite(hip_model.measured_alpha_notzli_deg) ? hip_model.measured_alpha_notzli_deg
                                                                     : hip_model.parameters.alpha_deg;
  hip.edge_mm = hip_model.parameters.edge_mm;
  hip.dir = dir;
  hip.load_ms = milliseconds_since(start);
  hip.hash = hip_content_hash(hip_model, model.grid);
  const HipFeatures features = extract_hip_features(hip_model, model.grid);
  hip.features = features.values;
  hip.feature_ms = features.extraction_ms;
  hip.misses = features.misses;
  hip.values = values;
  const stats::PenetrationDepths depths = penetration_over_motion(model.angle_deg, hip_model, dir);
  for (Eigen::Index j = 0; j < depths.curvilinear_mm.cols(); ++j) {
    hip.curvilinear_mm.push_back(depths.curvilinear_mm(0, j));
    hip.radial_mm.push_back(depths.radial_mm(0, j));
  }
  const auto existing = std::find_if(model.hips.begin(), model.hips.end(), [&](const TrainingHip& h) { return h.hash == hip.hash; });
  if (existing != model.hips.end()) {
    if (notes) notes->push_back(hip.name + ": FE values replaced by those of " + table_file.string());
    *existing = std::move(hip);
  } else {
    model.hips.push_back(std::move(hip));
  }
#else
  (void)model, (void)dir, (void)measure, (void)notes;
  throw_error(table_file.string(), ": reading an `fem run` table's HDF5 needs the FE module (HIPFAI_WITH_FEM)");
#endif
}

}  // namespace

FeSweep read_fe_sweep(const std::filesystem::path& fe, const std::string& measure) {
  if (is_fem_sweep_folder(fe)) {
#ifdef HIPFAI_WITH_FEM
    return read_fem_sweep_folder(fe, measure);
#else
    throw_error(fe.string(), ": a scripts/fem-sweep folder; reading it needs the FE module (HIPFAI_WITH_FEM)");
#endif
  }
  const std::filesystem::path file = std::filesystem::is_directory(fe) ? fe / "steps.csv" : fe;
  std::ifstream in(file);
  if (!in) throw_error(file.string(), ": cannot read the FE table (expected a `hipfai study validate` folder)");
  std::string line;
  if (!std::getline(in, line)) throw_error(file.string(), ": empty");
  const auto header = split_csv_line(line);
  // Index of a column; header.size() when there is none.
  const auto optional_column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const auto column = [&](const std::string& name) {
    const std::size_t index = optional_column(name);
    if (index == header.size()) throw_error(file.string(), ": no column ", name);
    return index;
  };
  const std::size_t ce = column("ce_deg"), alpha = column("alpha_deg"), step = column("step"),
                    angle = column("angle_deg"), value = column(measure);
  // The penetration depths of `hipfai study validate` (optional: other tables have none).
  const std::size_t curvilinear = optional_column("max_curvilinear_mm"), radial = optional_column("max_radial_mm");
  if (measure.size() < 4 || measure.substr(measure.size() - 4) != "_mpa") {
    throw_error(file.string(), ": ", measure, " is not an FE measure (names end in _mpa)");
  }
  FeSweep sweep;
  sweep.measure = measure;
  struct Row {
    double angle, value, curvilinear, radial;
  };
  std::map<std::pair<double, double>, std::map<int, Row>> rows;  // hip -> step -> row
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const auto cells = split_csv_line(line);
    if (cells.size() != header.size()) {
      throw_error(file.string(), ":", line_number, ": ", cells.size(), " cells, the header has ", header.size());
    }
    const double c = table_number(cells[ce]), a = table_number(cells[alpha]), s = table_number(cells[step]),
                 g = table_number(cells[angle]);
    if (!std::isfinite(c) || !std::isfinite(a) || !std::isfinite(s) || !std::isfinite(g) || s < 1 ||
        s != std::floor(s)) {
      throw_error(file.string(), ":", line_number, ": bad ce_deg, alpha_deg, step or angle_deg");
    }
    double c_mm = kNaN, r_mm = kNaN;
    if (curvilinear < header.size() && radial < header.size()) {
      c_mm = table_number(cells[curvilinear]);
      r_mm = table_number(cells[radial]);
      if (!(c_mm >= 0.0) || !(r_mm >= 0.0) || !std::isfinite(c_mm) || !std::isfinite(r_mm)) {
        throw_error(file.string(), ":", line_number, ": bad max_curvilinear_mm or max_radial_mm (a depth >= 0 in mm)");
      }
    }
    rows[{c, a}][static_cast<int>(s)] = {g, table_number(cells[value]), c_mm, r_mm};
  }
  if (rows.empty()) throw_error(file.string(), ": no rows");
  int steps = 0;
  for (const auto& [hip, by_step] : rows) steps = std::max(steps, by_step.rbegin()->first);
  sweep.angle_deg.assign(static_cast<std::size_t>(steps), kNaN);
  const auto edges = read_edges(file.parent_path() / "timings.csv");
  for (const auto& [hip, by_step] : rows) {
    const std::vector<double> unknown(static_cast<std::size_t>(steps), kNaN);
    FeSweepHip entry{hip.first, hip.second, kNaN, unknown, unknown, unknown};
    if (const auto it = edges.find(hip); it != edges.end()) entry.edge_mm = it->second;
    for (const auto& [s, row] : by_step) {
      double& known = sweep.angle_deg[static_cast<std::size_t>(s - 1)];
      if (std::isnan(known)) known = row.angle;
      if (std::abs(known - row.angle) > 1e-6) {
        throw_error(file.string(), ": hip ", hip_name(hip.first, hip.second), " step ", s, " is at ",
                    row.angle, " deg, another hip's at ", known, " deg: one motion per table");
      }
      entry.values[static_cast<std::size_t>(s - 1)] = row.value;
      entry.curvilinear_mm[static_cast<std::size_t>(s - 1)] = row.curvilinear;
      entry.radial_mm[static_cast<std::size_t>(s - 1)] = row.radial;
    }
    sweep.hips.push_back(std::move(entry));
  }
  for (std::size_t k = 0; k < sweep.angle_deg.size(); ++k) {
    if (std::isnan(sweep.angle_deg[k])) throw_error(file.string(), ": no hip has step ", k + 1);
  }
  return sweep;
}

stats::PenetrationDepths training_depths(const std::vector<TrainingHip>& hips, Eigen::Index steps) {
  const auto m = static_cast<Eigen::Index>(hips.size());
  stats::PenetrationDepths depths{Eigen::MatrixXd(m, steps), Eigen::MatrixXd(m, steps)};
  for (Eigen::Index i = 0; i < m; ++i) {
    const TrainingHip& hip = hips[static_cast<std::size_t>(i)];
    if (hip.curvilinear_mm.size() < static_cast<std::size_t>(steps) || hip.radial_mm.size() < static_cast<std::size_t>(steps)) {
      return {};
    }
    for (Eigen::Index j = 0; j < steps; ++j) {
      depths.curvilinear_mm(i, j) = hip.curvilinear_mm[static_cast<std::size_t>(j)];
      depths.radial_mm(i, j) = hip.radial_mm[static_cast<std::size_t>(j)];
    }
  }
  if (m == 0 || !depths.curvilinear_mm.allFinite() || !depths.radial_mm.allFinite()) return {};
  return depths;
}

namespace {

// Retraining: the base model's grid, motion and hips, after checking that they are the ones asked for.
void start_from_base(EstimatorModel& model, const EstimatorTrainOptions& options) {
  EstimatorModel base = read_estimator_model(options.base_model);
  if (options.grid_given && base.grid.describe() != options.grid.describe()) {
    throw_error(options.base_model.string(), ": trained on feature grid '", base.grid.describe(),
                "', not the requested '", options.grid.describe(), "'; features on different grids cannot be mixed");
  }
  if (base.measure != options.measure) {
    throw_error(options.base_model.string(), ": trained on ", base.measure, ", not ", options.measure);
  }
  model.grid = base.grid;
  model.angle_deg = base.angle_deg;
  model.hips = std::move(base.hips);
}

// The hip folder of one FE hip (same CE/alpha, and edge when the FE results give it) and its
// content hash; copies of one hip (a cache holding the same generated hip under two keys) are one hip.
const HipFolder& matching_folder(const std::vector<HipFolder>& folders, const FeSweepHip& fe_hip,
                                 const EstimatorTrainOptions& options, const FeatureGrid& grid, std::string& hash) {
  std::vector<const HipFolder*> matches;
  for (const HipFolder& folder : folders) {
    const auto& p = folder.model.parameters;
    if (same(p.ce_deg, fe_hip.ce_deg) && same(p.alpha_deg, fe_hip.alpha_deg) &&
        (std::isnan(fe_hip.edge_mm) || same(p.edge_mm, fe_hip.edge_mm))) {
      matches.push_back(&folder);
    }
  }
  if (matches.empty()) {
    throw_error(options.hips.string(), ": no hip folder with CE ", fe_hip.ce_deg, ", alpha ", fe_hip.alpha_deg,
                std::isnan(fe_hip.edge_mm) ? std::string() : ", edge " + digits17(fe_hip.edge_mm) + " mm",
                " (the FE results have it)");
  }
  hash = hip_content_hash(matches.front()->model, grid);
  bool copies = true;
  for (std::size_t k = 1; k < matches.size() && copies; ++k) {
    copies = hip_content_hash(matches[k]->model, grid) == hash;
  }
  if (!copies) {
    throw_error(options.hips.string(), ": ", matches.size(), " hip folders match ",
                hip_name(fe_hip.ce_deg, fe_hip.alpha_deg), " (", matches[0]->dir.filename().string(), ", ",
                matches[1]->dir.filename().string(),
                ") with different meshes; give a folder with one hip per CE/alpha, or the FE folder's "
                "timings.csv with edge_mm");
  }
  return *matches.front();
}

TrainingHip training_hip(const HipFolder& folder, const FeSweepHip& fe_hip, const std::string& hash,
                         const FeatureGrid& grid) {
  TrainingHip hip;
  hip.name = hip_name(fe_hip.ce_deg, fe_hip.alpha_deg);
  hip.ce_deg = fe_hip.ce_deg;
  hip.alpha_deg = fe_hip.alpha_deg;
  hip.edge_mm = folder.model.parameters.edge_mm;
  hip.dir = folder.dir;
  hip.load_ms = folder.load_ms;
  hip.hash = hash;
  const HipFeatures features = extract_hip_features(folder.model, grid);
  hip.features = features.values;
  hip.feature_ms = features.extraction_ms;
  hip.misses = features.misses;
  hip.values = fe_hip.values;
  hip.curvilinear_mm = fe_hip.curvilinear_mm;
  hip.radial_mm = fe_hip.radial_mm;
  return hip;
}

// The same hip again (another FE level, a re-run): the newer FE values replace the older.
// Same = same sampled meshes AND same CE/alpha: a grid of bones only (femur_bone) samples the same
// meshes for hips that differ in their sockets, which stay separate hips.
void add_or_replace(EstimatorModel& model, TrainingHip hip, const std::string& measure,
                    std::vector<std::string>* notes) {
  const auto existing = std::find_if(model.hips.begin(), model.hips.end(), [&](const TrainingHip& h) {
    return h.hash == hip.hash && same(h.ce_deg, hip.ce_deg) && same(h.alpha_deg, hip.alpha_deg);
  });
  if (existing != model.hips.end()) {
    if (notes) notes->push_back(hip.name + ": FE values replaced by those of " + measure + " in the new results");
    *existing = std::move(hip);
  } else {
    model.hips.push_back(std::move(hip));
  }
}

// Every hip of the FE sweeps, matched to its folder under --hips and its features extracted.
void add_sweep_hips(EstimatorModel& model, const std::vector<FeSweep>& sweeps, const EstimatorTrainOptions& options,
                    std::vector<std::string>* notes) {
  if (options.hips.empty()) throw_error("train: --hips (the hip folders of the FE results) is required");
  const std::vector<HipFolder> folders = load_hip_folders(options.hips, model.grid, options.progress);
  std::size_t total = 0;
  for (const auto& sweep : sweeps) total += sweep.hips.size();
  ProgressBar bar("hip features", total, options.progress);
  for (const auto& sweep : sweeps) {
    for (const FeSweepHip& fe_hip : sweep.hips) {
      std::string hash;
      const HipFolder& folder = matching_folder(folders, fe_hip, options, model.grid, hash);
      add_or_replace(model, training_hip(folder, fe_hip, hash, model.grid), sweep.measure, notes);
      bar.advance();
    }
  }
}

}  // namespace

EstimatorModel train_estimator_model(const EstimatorTrainOptions& options, std::vector<std::string>* notes) {
  if (options.fe.empty() && options.base_model.empty()) throw_error("train: no FE results (--fe) given");
  EstimatorModel model;
  model.grid = options.grid;
  model.measure = options.measure;
  stats::EstimatorSettings settings = options.settings;
  if (!options.base_model.empty()) start_from_base(model, options);
  std::vector<FeSweep> sweeps;
  for (const auto& fe : options.fe) {
    sweeps.push_back(read_fe_sweep(fe, options.measure));
    if (model.angle_deg.empty()) model.angle_deg = sweeps.back().angle_deg;
    check_same_motion(model.angle_deg, sweeps.back().angle_deg,
                      fe.string() + (options.base_model.empty() ? "" : " vs " + options.base_model.string()));
  }
  if (!sweeps.empty()) add_sweep_hips(model, sweeps, options, notes);
  for (const auto& [dir, table_file] : options.fe_hips) add_fe_hip(model, dir, table_file, options.measure, notes);
  fit_estimator_model(model, settings);
  return model;
}

TrainingHip training_hip_from_folder(const std::filesystem::path& dir, FeSweepHip fe, const FeatureGrid& grid) {
  const std::set<std::string> tissues(grid.tissues.begin(), grid.tissues.end());
  const auto start = std::chrono::steady_clock::now();
  HipFolder folder{dir, geometry::load_hip_model(dir, tissues), 0};
  folder.load_ms = milliseconds_since(start);
  fe.ce_deg = folder.model.parameters.ce_deg;
  fe.alpha_deg = folder.model.parameters.alpha_deg;
  TrainingHip hip = training_hip(folder, fe, hip_content_hash(folder.model, grid), grid);
  hip.name = dir.filename().string();
  return hip;
}

void fit_estimator_model(EstimatorModel& model, const stats::EstimatorSettings& settings) {
  const auto rows = static_cast<Eigen::Index>(model.hips.size());
  if (rows < 3) throw_error("train: ", rows, " hips with FE results; the estimator needs at least 3");
  Eigen::MatrixXd features(rows, model.grid.num_features());
  Eigen::MatrixXd values(rows, static_cast<Eigen::Index>(model.angle_deg.size()));
  for (Eigen::Index i = 0; i < rows; ++i) {
    const TrainingHip& hip = model.hips[static_cast<std::size_t>(i)];
    features.row(i) = hip.features.transpose();
    for (Eigen::Index j = 0; j < values.cols(); ++j) values(i, j) = hip.values[static_cast<std::size_t>(j)];
  }
  model.estimator = stats::train_estimator(features, values, settings, training_depths(model.hips, values.cols()));
  model.code_version = std::string(kVersion) + " " + kGitSha;
}

namespace {

// The hip's curvilinear and radial depth at each step of the model's motion, computed as `hipfai
// study validate` computes the FE table's (same method, default options).
stats::PenetrationDepths penetration_over_model_motion(const EstimatorModel& model, const geometry::HipModel& hip,
                                                       const std::filesystem::path& hip_dir) {
  if (!model.estimator.depths.known()) {
    throw_error("depth_nn needs the training hips' penetration depths, and this model has none (trained from an FE "
                "table without max_curvilinear_mm / max_radial_mm)");
  }
  return penetration_over_motion(model.angle_deg, hip, hip_dir);
}

stats::PenetrationDepths penetration_over_motion(const std::vector<double>& angle_deg, const geometry::HipModel& hip,
                                                 const std::filesystem::path& hip_dir) {
  const auto p = static_cast<int>(angle_deg.size());
  const Motion motion = standing_to_sitting(p);
  for (int j = 0; j < p; ++j) {
    if (std::abs(motion.steps[static_cast<std::size_t>(j)].angle_deg - angle_deg[static_cast<std::size_t>(j)]) > 1e-6) {
      throw_error(hip_dir.string(), ": the motion (", p, " steps to ", angle_deg.back(), " deg) is not standing-to-sitting in ",
                  p, " sub-motions, the only motion whose penetration depths the estimator computes");
    }
  }
  std::string missing;
  for (const char* tissue : {"femur_bone", "labrum", "femoral_cartilage", "acetabular_cartilage"}) {
    if (!hip.tissues.count(tissue)) missing += (missing.empty() ? "" : ", ") + std::string(tissue);
  }
  if (!missing.empty()) {
    throw_error(hip_dir.string(), ": no ", missing, "; depth_nn computes the curvilinear and radial penetration, "
                "which need them");
  }
  const LoadedHip loaded = loaded_hip_from_model(hip, hip_dir.filename().string());
  StageLog log;
  const PenetrationRun run = compute_penetration(loaded, motion, PenetrationOptions{}, log);
  const std::vector<double> curvilinear = run.curvilinear_maxima_mm(), radial = run.radial_maxima_mm();
  return {Eigen::Map<const Eigen::MatrixXd>(curvilinear.data(), 1, p),
          Eigen::Map<const Eigen::MatrixXd>(radial.data(), 1, p)};
}

}  // namespace

HipPrediction predict_hip(const EstimatorModel& model, const std::filesystem::path& hip_dir,
                          stats::EstimatorMethod method, int e_prime) {
  const bool segmented = !std::filesystem::exists(hip_dir / "model.json") && std::filesystem::exists(hip_dir / "hip.json");
  if (!segmented && !std::filesystem::exists(hip_dir / "model.json")) {
    throw_error(hip_dir.string(), ": no model.json (a hip model folder, e.g. from `hipfai generate`) nor hip.json "
                "(a segmented hip)");
  }
  HipPrediction prediction;
  prediction.approximate_frame = segmented;
  auto start = std::chrono::steady_clock::now();
  // All tissues are read (the file says which exist), so a missing one is named below. A
  // segmented hip (bones from a scan) gets the approximate frame of its bones.
  const geometry::HipModel hip = segmented ? load_segmented_hip(hip_dir) : geometry::load_hip_model(hip_dir);
  std::string missing, present;
  for (const auto& name : model.grid.tissues) {
    if (!hip.tissues.count(name)) missing += (missing.empty() ? "" : ", ") + name;
  }
  for (const auto& [name, mesh] : hip.tissues) present += (present.empty() ? "" : ", ") + name;
  if (!missing.empty()) {
    throw_error(hip_dir.string(), ": no ", missing, " (it has ", present, "); the model's features (",
                model.grid.describe(), ") need every one of them (refused, not filled in)",
                segmented ? "; a model of the bones it has: `estimator train --tissues femur_bone`" : "");
  }
  prediction.load_ms = milliseconds_since(start);
  const HipFeatures features = extract_hip_features(hip, model.grid);
  prediction.feature_ms = features.extraction_ms;
  prediction.misses = features.misses;
  if (stats::needs_depths(method)) {
    start = std::chrono::steady_clock::now();
    prediction.depths = penetration_over_model_motion(model, hip, hip_dir);
    prediction.penetration_ms = milliseconds_since(start);
  }
  start = std::chrono::steady_clock::now();
  prediction.result = stats::estimate(model.estimator, features.values, method, e_prime, prediction.depths);
  prediction.predict_ms = milliseconds_since(start);
  return prediction;
}

stats::EPrimeSelection choose_e_prime(const EstimatorModel& model, stats::EstimatorMethod method) {
  return stats::select_e_prime(model.estimator.features, model.estimator.values, model.estimator.settings, method,
                               model.estimator.pca.num_components());
}

}  // namespace hipfai::studies
