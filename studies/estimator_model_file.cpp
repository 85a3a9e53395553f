// hipfai — the HDF5 file of a trained estimator model (see estimator_model_file.h).
#include "studies/estimator_model_file.h"

#include "core/error.h"
#include "core/numbers.h"
#include "core/text_format.h"
#include "studies/results/results_file.h"

#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::studies {

namespace {

using hipfai::kNaN;
constexpr const char* kModelFormat = "hipfai-pressure-estimator";
constexpr int kModelVersion = 1;
// Value of the root attribute penetration_depths when the two depth datasets are stored.
constexpr const char* kDepthDatasets = "/training/curvilinear_mm,/training/radial_mm";

}  // namespace

void write_estimator_model(const EstimatorModel& model, const std::filesystem::path& path) {
  const stats::TrainedEstimator& e = model.estimator;
  const auto f = static_cast<std::size_t>(e.features.cols());
  const auto row_major = [](const Eigen::MatrixXd& matrix) {
    std::vector<double> out(static_cast<std::size_t>(matrix.size()));
    for (Eigen::Index r = 0; r < matrix.rows(); ++r) {
      for (Eigen::Index c = 0; c < matrix.cols(); ++c) out[static_cast<std::size_t>(r * matrix.cols() + c)] = matrix(r, c);
    }
    return out;
  };
  const auto vec = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  ResultsFile file(path);
  file.set_attribute("/", "format", kModelFormat);
  file.set_attribute("/", "format_version", std::to_string(kModelVersion));
  file.set_attribute("/", "code_version", model.code_version);
  file.set_attribute("/", "units", "mm (features), deg (angles), MPa (FE values)");
  file.set_attribute("/", "fe_measure", model.measure);
  file.set_attribute("/", "feature_grid", model.grid.describe());
  file.set_attribute("/", "method", "thesis §4.5 PCA nearest-neighbour (Eq. 17-23); baselines knn, ridge");
  std::string names, hashes;
  for (const auto& hip : model.hips) {
    names += (names.empty() ? "" : ";") + hip.name;
    hashes += (hashes.empty() ? "" : ";") + hip.hash;
  }
  file.set_attribute("/", "training_hips", names);
  file.set_attribute("/", "training_hip_hashes", hashes);
  file.set_attribute("/", "settings",
                     "components=" + std::to_string(e.settings.pca.components) + ";scale_floor=" +
                         digits17(e.settings.pca.scale_floor) + ";nearest=" + std::to_string(e.settings.nearest) +
                         ";knn_k=" + std::to_string(e.settings.knn_k) +
                         ";bordering_min_variance_share=" + digits17(e.settings.bordering_min_variance_share));
  file.write("/motion/angle_deg", model.angle_deg, 1, "deg");
  file.write("/normalisation/mean", vec(e.pca.mean), 1, "mm");
  file.write("/normalisation/scale", vec(e.pca.scale), 1, "mm");
  file.write("/pca/basis", row_major(e.pca.basis), static_cast<std::size_t>(e.pca.basis.cols()), "1");
  file.write("/pca/variances", vec(e.pca.variances), 1, "1");
  file.write("/pca/total_variance", {e.pca.total_variance}, 1, "1");
  file.write("/training/features", row_major(e.features), f, "mm");
  file.write("/training/values", row_major(e.values), static_cast<std::size_t>(e.values.cols()), "MPa");
  std::vector<double> ce, alpha, edge;
  for (const auto& hip : model.hips) {
    ce.push_back(hip.ce_deg);
    alpha.push_back(hip.alpha_deg);
    edge.push_back(hip.edge_mm);
  }
  file.write("/training/ce_deg", ce, 1, "deg");
  file.write("/training/alpha_deg", alpha, 1, "deg");
  file.write("/training/edge_mm", edge, 1, "mm");
  // The penetration depths of the training hips (depth_nn), when every hip has them.
  file.set_attribute("/", "penetration_depths", e.depths.known() ? kDepthDatasets : "none");
  if (e.depths.known()) {
    file.write("/training/curvilinear_mm", row_major(e.depths.curvilinear_mm),
               static_cast<std::size_t>(e.depths.curvilinear_mm.cols()), "mm");
    file.write("/training/radial_mm", row_major(e.depths.radial_mm), static_cast<std::size_t>(e.depths.radial_mm.cols()),
               "mm");
  }
  file.commit();
}

namespace {

std::map<std::string, std::string> parse_settings(const std::string& text) {
  std::map<std::string, std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ';')) {
    const auto eq = item.find('=');
    if (eq != std::string::npos) out[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return out;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, separator)) out.push_back(item);
  return out;
}

// A dataset of the model as a rows x cols matrix; an expected size of -1 takes what the file has.
Eigen::MatrixXd read_matrix(ResultsReader& file, const std::filesystem::path& path, const std::string& name,
                            Eigen::Index rows_expected, Eigen::Index cols_expected) {
  std::size_t rows = 0, cols = 0;
  const std::vector<double> values = file.dataset(name, &rows, &cols);
  if ((rows_expected >= 0 && static_cast<Eigen::Index>(rows) != rows_expected) ||
      (cols_expected >= 0 && static_cast<Eigen::Index>(cols) != cols_expected)) {
    throw_error(path.string(), ": ", name, " is ", rows, " x ", cols, ", inconsistent with the rest of the model");
  }
  Eigen::MatrixXd matrix(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      matrix(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = values[r * cols + c];
    }
  }
  return matrix;
}

// Refuses a file that is not a model of this format.
void check_format(ResultsReader& file, const std::filesystem::path& path) {
  std::string format;
  try {
    format = file.string_attribute("/", "format");
  } catch (const Error&) {
    throw_error(path.string(), ": not a hipfai estimator model (not HDF5, or no format attribute)");
  }
  if (format != kModelFormat) throw_error(path.string(), ": not a hipfai estimator model (format '", format, "')");
}

void read_settings(ResultsReader& file, EstimatorModel& model) {
  model.code_version = file.string_attribute("/", "code_version");
  model.measure = file.string_attribute("/", "fe_measure");
  model.grid = parse_feature_grid(file.string_attribute("/", "feature_grid"));
  const auto settings = parse_settings(file.string_attribute("/", "settings"));
  stats::EstimatorSettings& s = model.estimator.settings;
  s.pca.components = std::stoi(settings.at("components"));
  s.pca.scale_floor = std::stod(settings.at("scale_floor"));
  s.nearest = std::stoi(settings.at("nearest"));
  s.knn_k = std::stoi(settings.at("knn_k"));
  s.bordering_min_variance_share = std::stod(settings.at("bordering_min_variance_share"));
}

// The training hips' penetration depths (m hips x p steps), when the model has them: models
// written before depth_nn have no penetration_depths attribute.
void read_depths(ResultsReader& file, const std::filesystem::path& path, Eigen::Index m, Eigen::Index p,
                 stats::TrainedEstimator& e) {
  std::string depth_datasets = "none";
  try {
    depth_datasets = file.string_attribute("/", "penetration_depths");
  } catch (const Error&) {
  }
  if (depth_datasets == kDepthDatasets) {
    e.depths = {read_matrix(file, path, "/training/curvilinear_mm", m, p),
                read_matrix(file, path, "/training/radial_mm", m, p)};
    if (!e.depths.curvilinear_mm.allFinite() || !e.depths.radial_mm.allFinite() ||
        (e.depths.curvilinear_mm.array() < 0.0).any() || (e.depths.radial_mm.array() < 0.0).any()) {
      throw_error(path.string(), ": penetration depths not finite and >= 0");
    }
  } else if (depth_datasets != "none") {
    throw_error(path.string(), ": penetration_depths is '", depth_datasets, "'");
  }
}

// One TrainingHip per row of the training tables, with its name, hash and angles.
void add_training_hips(EstimatorModel& model, const Eigen::MatrixXd& ce, const Eigen::MatrixXd& alpha,
                       const Eigen::MatrixXd& edge, const std::vector<std::string>& names,
                       const std::vector<std::string>& hashes) {
  const stats::TrainedEstimator& e = model.estimator;
  const Eigen::Index m = e.features.rows();
  const auto p = static_cast<Eigen::Index>(model.angle_deg.size());
  for (Eigen::Index i = 0; i < m; ++i) {
    TrainingHip hip;
    hip.name = names[static_cast<std::size_t>(i)];
    hip.hash = hashes[static_cast<std::size_t>(i)];
    hip.ce_deg = ce(i, 0);
    hip.alpha_deg = alpha(i, 0);
    hip.edge_mm = edge(i, 0);
    hip.features = e.features.row(i).transpose();
    hip.values.assign(static_cast<std::size_t>(p), kNaN);
    for (Eigen::Index j = 0; j < p; ++j) hip.values[static_cast<std::size_t>(j)] = e.values(i, j);
    if (e.depths.known()) {
      for (Eigen::Index j = 0; j < p; ++j) {
        hip.curvilinear_mm.push_back(e.depths.curvilinear_mm(i, j));
        hip.radial_mm.push_back(e.depths.radial_mm(i, j));
      }
    }
    model.hips.push_back(std::move(hip));
  }
}

// The settings, motion, normalisation, PCA, training tables and hips; throws hipfai::Error on
// anything missing or inconsistent.
void read_model(ResultsReader& file, const std::filesystem::path& path, EstimatorModel& model) {
  if (file.string_attribute("/", "format_version") != std::to_string(kModelVersion)) {
    throw_error("format_version is not ", kModelVersion, " (written by another hipfai version?)");
  }
  read_settings(file, model);
  const Eigen::Index f = model.grid.num_features();
  const Eigen::MatrixXd angles = read_matrix(file, path, "/motion/angle_deg", -1, 1);
  model.angle_deg.assign(angles.data(), angles.data() + angles.size());
  const auto p = static_cast<Eigen::Index>(model.angle_deg.size());
  stats::TrainedEstimator& e = model.estimator;
  e.pca.mean = read_matrix(file, path, "/normalisation/mean", f, 1).col(0);
  e.pca.scale = read_matrix(file, path, "/normalisation/scale", f, 1).col(0);
  e.pca.basis = read_matrix(file, path, "/pca/basis", f, -1);
  e.pca.variances = read_matrix(file, path, "/pca/variances", e.pca.basis.cols(), 1).col(0);
  e.pca.total_variance = read_matrix(file, path, "/pca/total_variance", 1, 1)(0, 0);
  e.features = read_matrix(file, path, "/training/features", -1, f);
  const Eigen::Index m = e.features.rows();
  e.values = read_matrix(file, path, "/training/values", m, p);
  const Eigen::MatrixXd ce = read_matrix(file, path, "/training/ce_deg", m, 1);
  const Eigen::MatrixXd alpha = read_matrix(file, path, "/training/alpha_deg", m, 1);
  const Eigen::MatrixXd edge = read_matrix(file, path, "/training/edge_mm", m, 1);
  read_depths(file, path, m, p, e);
  const auto names = split(file.string_attribute("/", "training_hips"), ';');
  const auto hashes = split(file.string_attribute("/", "training_hip_hashes"), ';');
  if (static_cast<Eigen::Index>(names.size()) != m || static_cast<Eigen::Index>(hashes.size()) != m) {
    throw_error(path.string(), ": ", names.size(), " hip names and ", hashes.size(), " hashes for ", m, " hips");
  }
  if (!e.pca.mean.allFinite() || !e.pca.scale.allFinite() || !e.pca.basis.allFinite() || !e.features.allFinite()) {
    throw_error(path.string(), ": non-finite numbers in the PCA or features");
  }
  add_training_hips(model, ce, alpha, edge, names, hashes);
  stats::derive_estimator(e);
}

}  // namespace

EstimatorModel read_estimator_model(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw_error(path.string(), ": no such model file");
  EstimatorModel model;
  // Every value of the model read in one child process (a damaged file is refused: studies/results/hdf5_child.h).
  ResultsReader file(path);
  file.prefetch({"/motion/angle_deg", "/normalisation/mean", "/normalisation/scale", "/pca/basis",
                 "/pca/variances", "/pca/total_variance", "/training/features", "/training/values",
                 "/training/ce_deg", "/training/alpha_deg", "/training/edge_mm", "/training/curvilinear_mm",
                 "/training/radial_mm"},
                {{"/", "format"}, {"/", "format_version"}, {"/", "code_version"}, {"/", "fe_measure"},
                 {"/", "feature_grid"}, {"/", "settings"}, {"/", "training_hips"}, {"/", "training_hip_hashes"},
                 {"/", "penetration_depths"}});
  check_format(file, path);
  try {
    read_model(file, path, model);
  } catch (const Error& error) {
    std::string message = error.what();
    if (message.rfind(path.string() + ": ", 0) == 0) message = message.substr(path.string().size() + 2);
    throw_error(path.string(), ": corrupt estimator model (", message, ")");
  } catch (const std::exception& error) {
    throw_error(path.string(), ": corrupt estimator model (", error.what(), ")");
  }
  return model;
}

}  // namespace hipfai::studies
