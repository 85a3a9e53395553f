#include "studies/pipeline/motion.h"

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/literature.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

namespace hipfai::studies {

namespace {

void set_axis_angle(MotionStep& step) {
  const Eigen::AngleAxisd axis_angle(step.rotation);
  step.angle_deg = axis_angle.angle() * geometry::kRadToDeg;
  // The neutral pose has no axis; keep +X (flexion) so downstream code always has a unit vector.
  step.axis = step.angle_deg > 1e-12 ? Eigen::Vector3d(axis_angle.axis()) : Eigen::Vector3d::UnitX();
}

}  // namespace

MotionStep make_step(const geometry::HipPoseDeg& pose) {
  MotionStep step;
  step.pose = pose;
  step.rotation = geometry::femur_rotation(pose);
  set_axis_angle(step);
  return step;
}

std::string pose_sequence_name(geometry::PoseSequence sequence) {
  return sequence == geometry::PoseSequence::kFixedAxes ? "fixed-axes" : "jcs";
}

geometry::PoseSequence pose_sequence_from_name(const std::string& name) {
  if (name == "jcs") return geometry::PoseSequence::kJointCoordinateSystem;
  if (name == "fixed-axes") return geometry::PoseSequence::kFixedAxes;
  throw_error("pose sequence '", name, "' is not one of: jcs, fixed-axes");
}

Motion standing_to_sitting(int sub_motions, geometry::PoseSequence sequence) {
  if (sub_motions < 1) throw_error("standing_to_sitting: sub_motions must be >= 1, got ", sub_motions);
  MotionStep end;
  end.rotation = geometry::femur_rotation({literature::kStandToSitFlexionDeg, literature::kStandToSitAdductionDeg,
                                           literature::kStandToSitInternalRotationDeg},
                                          sequence);
  set_axis_angle(end);
  Motion motion;
  motion.name = sequence == geometry::PoseSequence::kFixedAxes ? "standing_to_sitting_fixed_axes"
                                                                : "standing_to_sitting";
  for (int k = 1; k <= sub_motions; ++k) {
    MotionStep step;
    step.axis = end.axis;
    step.angle_deg = end.angle_deg * k / sub_motions;
    step.rotation =
        Eigen::AngleAxisd(step.angle_deg * geometry::kDegToRad, step.axis).toRotationMatrix();
    // Cardan angles of the intermediate pose, X-Y'-Z'' (inverse of femur_rotation).
    const Eigen::Vector3d xyz = step.rotation.eulerAngles(0, 1, 2) * geometry::kRadToDeg;
    step.pose = {xyz.x(), xyz.y(), xyz.z()};
    motion.steps.push_back(step);
  }
  return motion;
}

const std::vector<std::string>& medical_rotation_names() {
  static const std::vector<std::string> names{"flexion",   "extension",         "abduction",
                                              "adduction", "internal_rotation", "external_rotation"};
  return names;
}

Motion medical_rotation(const std::string& which, double max_deg, int steps) {
  if (steps < 1) throw_error("medical rotation: steps must be >= 1, got ", steps);
  if (!(max_deg > 0.0 && max_deg <= 180.0)) {
    throw_error("medical rotation: max angle must be in (0, 180] deg, got ", max_deg);
  }
  Motion motion;
  motion.name = which;
  for (int k = 1; k <= steps; ++k) {
    const double angle = max_deg * k / steps;
    geometry::HipPoseDeg pose;
    if (which == "flexion") pose.flexion_deg = angle;
    else if (which == "extension") pose.flexion_deg = -angle;
    else if (which == "adduction") pose.adduction_deg = angle;
    else if (which == "abduction") pose.adduction_deg = -angle;
    else if (which == "internal_rotation") pose.internal_rotation_deg = angle;
    else if (which == "external_rotation") pose.internal_rotation_deg = -angle;
    else throw_error("unknown medical rotation '", which, "'");
    motion.steps.push_back(make_step(pose));
  }
  return motion;
}

Motion read_motion_csv(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw_error(path.string(), ": cannot open motion file");
  std::ostringstream text;
  text << file.rdbuf();
  return parse_motion_csv(text.str(), path);
}

Motion parse_motion_csv(const std::string& text, const std::filesystem::path& path) {
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    header = split_csv_line(line);
  }
  const std::vector<std::string> required{"step", "flexion_deg", "adduction_deg",
                                          "internal_rotation_deg"};
  const std::vector<std::string> force{"Fx_N", "Fy_N", "Fz_N"};
  if (header.size() < 4 || !std::equal(required.begin(), required.end(), header.begin())) {
    throw_error(path.string(), ":", line_number,
                ": header must start with step,flexion_deg,adduction_deg,internal_rotation_deg");
  }
  const bool has_force = header.size() >= 7 && std::equal(force.begin(), force.end(), header.begin() + 4);
  if (header.size() != 4 && !has_force) {
    throw_error(path.string(), ":", line_number, ": optional force columns must be Fx_N,Fy_N,Fz_N");
  }
  Motion motion;
  motion.name = path.stem().string();
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const auto cells = split_csv_line(line);
    if (cells.size() != header.size()) {
      throw_error(path.string(), ":", line_number, ": expected ", header.size(), " values, found ",
                  cells.size());
    }
    std::vector<double> values;
    for (const auto& cell : cells) {
      double value = 0.0;
      const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
      if (cell.empty() || error != std::errc() || end != cell.data() + cell.size() ||
          !std::isfinite(value)) {
        throw_error(path.string(), ":", line_number, ": '", cell, "' is not a finite number");
      }
      values.push_back(value);
    }
    for (int a = 1; a <= 3; ++a) {
      if (std::abs(values[a]) > 180.0) {
        throw_error(path.string(), ":", line_number, ": ", header[a], " = ", values[a],
                    " is outside [-180, 180] deg (angles are in degrees)");
      }
    }
    MotionStep step = make_step({values[1], values[2], values[3]});
    if (has_force) step.force_N = Eigen::Vector3d(values[4], values[5], values[6]);
    motion.steps.push_back(step);
  }
  if (motion.steps.empty()) throw_error(path.string(), ": motion file has no steps");
  return motion;
}

void write_motion_csv(const Motion& motion, const std::filesystem::path& path) {
  const bool with_force = !motion.steps.empty() &&
                          std::all_of(motion.steps.begin(), motion.steps.end(),
                                      [](const MotionStep& step) { return step.force_N.has_value(); });
  write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    out << "step,flexion_deg,adduction_deg,internal_rotation_deg" << (with_force ? ",Fx_N,Fy_N,Fz_N" : "")
        << '\n';
    for (std::size_t k = 0; k < motion.steps.size(); ++k) {
      const MotionStep& step = motion.steps[k];
      out << k + 1 << ',' << step.pose.flexion_deg << ',' << step.pose.adduction_deg << ','
          << step.pose.internal_rotation_deg;
      if (with_force) out << ',' << step.force_N->x() << ',' << step.force_N->y() << ',' << step.force_N->z();
      out << '\n';
    }
  });
}

Eigen::Vector3d sitting_down_force_n(double phase, const SittingDownLoadOptions& options) {
  if (!(options.body_weight_n > 0.0) || !std::isfinite(options.body_weight_n)) {
    throw_error("sitting-down load: body weight must be > 0 N, got ", options.body_weight_n);
  }
  if (!(options.peak_phase > 0.0 && options.peak_phase <= 1.0)) {
    throw_error("sitting-down load: peak phase must be in (0, 1], got ", options.peak_phase);
  }
  for (const double percent : {options.start_percent_bw, options.peak_percent_bw, options.end_percent_bw}) {
    if (!(percent >= 0.0) || !std::isfinite(percent)) {
      throw_error("sitting-down load: %BW values must be finite and >= 0, got ", percent);
    }
  }
  if (!(std::abs(options.frontal_angle_deg) < 90.0 && std::abs(options.sagittal_angle_deg) < 90.0)) {
    throw_error("sitting-down load: direction angles must be within (-90, 90) deg");
  }
  if (!(phase >= 0.0 && phase <= 1.0)) throw_error("sitting-down load: phase must be in [0, 1], got ", phase);
  // Half-cosine blend: zero slope at both ends of each phase, so the peak is a smooth maximum
  // and the curve is monotonic within each phase.
  const auto blend = [](double from, double to, double s) {
    return from + (to - from) * 0.5 * (1.0 - std::cos(std::numbers::pi * s));
  };
  double percent = 0.0;
  if (phase <= options.peak_phase) {
    percent = blend(options.start_percent_bw, options.peak_percent_bw, phase / options.peak_phase);
  } else {
    percent = blend(options.peak_percent_bw, options.end_percent_bw,
                    (phase - options.peak_phase) / (1.0 - options.peak_phase));
  }
  const Eigen::Vector3d direction =
      Eigen::Vector3d(-std::tan(options.frontal_angle_deg * geometry::kDegToRad),
                      std::tan(options.sagittal_angle_deg * geometry::kDegToRad), 1.0)
          .normalized();
  return percent / 100.0 * options.body_weight_n * direction;
}

void attach_sitting_down_load(Motion& motion, const SittingDownLoadOptions& options) {
  const std::size_t n = motion.steps.size();
  for (std::size_t k = 0; k < n; ++k) {
    motion.steps[k].force_N = sitting_down_force_n(static_cast<double>(k + 1) / n, options);
  }
}

}  // namespace hipfai::studies
