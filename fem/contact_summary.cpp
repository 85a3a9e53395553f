#include "fem/contact_summary.h"

#include "core/parallel.h"
#include "fem/peak_measures.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::fem {

namespace {

geometry::Vec3 to_vec3(const dealii::Point<3>& point) { return {point[0], point[1], point[2]}; }
dealii::Point<3> to_point(const geometry::Vec3& vector) {
  return {vector[0], vector[1], vector[2]};
}

// The ball-averaged peak, or NaN when a sample is not finite (a diverged solve): make_finite
// then zeroes it and the result is reported as kNonFinite, like every other summary.
BallPeak ball_peak_or_nan(const std::vector<FieldSample>& samples, double radius_mm) {
  for (const FieldSample& sample : samples) {
    if (!std::isfinite(sample.value) || !(sample.weight > 0.0) || !std::isfinite(sample.weight) ||
        !sample.position_mm.allFinite()) {
      BallPeak peak;
      peak.value = std::numeric_limits<double>::quiet_NaN();
      return peak;
    }
  }
  return ball_averaged_peak(samples, radius_mm);
}

}  // namespace

void summarize_contact(const std::vector<SlaveNode>& nodes, const std::vector<bool>& active,
                       const std::vector<double>& force, const std::vector<double>& gap,
                       std::size_t n_pairs, double radius_mm, ContactResult& result) {
  result.pair_force_n.assign(n_pairs, dealii::Tensor<1, 3>());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const SlaveNode& node = nodes[n];
    ContactNode out;
    out.pair = node.pair;
    out.position_mm = node.position;
    out.normal = node.normal;
    out.area_mm2 = node.area;
    out.active = active[n];
    out.force_n =
        active[n] && n < force.size() ? force[n] : 0.0;  // no force: the loop stopped early
    out.pressure_mpa = out.force_n / node.area;
    out.gap_mm = gap.empty() ? node.initial_gap : gap[n];
    result.peaks.max_penetration_mm = std::max(result.peaks.max_penetration_mm, -out.gap_mm);
    result.pair_force_n[node.pair] += out.force_n * node.normal;
    result.nodes.push_back(out);
  }
  double total_force = 0.0;
  std::vector<FieldSample> pressure_samples;
  std::vector<unsigned int> pair_of_sample;
  for (const ContactNode& node : result.nodes) {
    if (!node.active) continue;
    result.peaks.contact_area_mm2 += node.area_mm2;
    total_force += node.force_n;
    if (node.pressure_mpa > result.peaks.max_pressure_mpa) {
      result.peaks.max_pressure_mpa = node.pressure_mpa;
      result.peaks.max_pressure_position_mm = node.position_mm;
      result.peaks.max_pressure_pair = static_cast<int>(node.pair);
    }
    pressure_samples.push_back({to_vec3(node.position_mm), node.pressure_mpa, node.area_mm2});
    pair_of_sample.push_back(node.pair);
  }
  if (result.peaks.contact_area_mm2 > 0.0)
    result.peaks.mean_pressure_mpa = total_force / result.peaks.contact_area_mm2;
  result.peaks.peak_average_radius_mm = radius_mm;
  const BallPeak pressure_peak = ball_peak_or_nan(pressure_samples, radius_mm);
  result.peaks.ball_peak_pressure_mpa = pressure_peak.value;
  result.peaks.ball_peak_pressure_position_mm = to_point(pressure_peak.position_mm);
  if (pressure_peak.found)
    result.peaks.ball_peak_pressure_pair = static_cast<int>(pair_of_sample[pressure_peak.sample]);
}

void summarize_stress(const VonMisesField& field, double radius_mm, ContactResult& result,
                      std::size_t n_threads) {
  const std::size_t n_bodies = field.samples.size();
  result.peaks.max_von_mises_mpa.assign(n_bodies, 0.0);
  result.peaks.p95_von_mises_mpa.assign(n_bodies, 0.0);
  result.peaks.ball_peak_von_mises_mpa.assign(n_bodies, 0.0);
  result.peaks.ball_peak_von_mises_position_mm.assign(n_bodies, dealii::Point<3>());
  // The bodies on the threads, each into its own slots.
  parallel_blocks(n_bodies, static_cast<int>(n_threads), 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t b = first; b < last; ++b) {
      // Per body: a ball at a tissue boundary averages that tissue only.
      const BallPeak peak = ball_peak_or_nan(field.samples[b], radius_mm);
      result.peaks.ball_peak_von_mises_mpa[b] = peak.value;
      result.peaks.ball_peak_von_mises_position_mm[b] = to_point(peak.position_mm);
      if (field.samples[b].empty()) continue;
      std::vector<double> values;
      values.reserve(field.samples[b].size());
      for (const FieldSample& sample : field.samples[b]) values.push_back(sample.value);
      std::sort(values.begin(), values.end());
      result.peaks.max_von_mises_mpa[b] = values.back();
      // Nearest-rank 95th percentile.
      const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * values.size()));
      result.peaks.p95_von_mises_mpa[b] = values[std::max<std::size_t>(rank, 1) - 1];
    }
  });
}

bool make_finite(ContactResult& result, dealii::Vector<double>& displacement) {
  bool finite = true;
  const auto fix = [&finite](double& value) {
    if (!std::isfinite(value)) {
      finite = false;
      value = 0.0;
    }
  };
  const auto fix_tensor = [&fix](dealii::Tensor<1, 3>& tensor) {
    for (unsigned int d = 0; d < 3; ++d) fix(tensor[d]);
  };
  for (double& value : displacement) fix(value);
  for (ContactNode& node : result.nodes) {
    fix(node.force_n);
    fix(node.pressure_mpa);
    fix(node.gap_mm);
  }
  for (auto& force : result.pair_force_n) fix_tensor(force);
  for (auto& translation : result.rigid_translation_mm) fix_tensor(translation);
  for (double* value : {&result.peaks.max_penetration_mm, &result.peaks.contact_area_mm2,
                        &result.peaks.max_pressure_mpa, &result.peaks.mean_pressure_mpa}) {
    fix(*value);
  }
  for (double& value : result.peaks.max_von_mises_mpa) fix(value);
  for (double& value : result.peaks.p95_von_mises_mpa) fix(value);
  for (double& value : result.peaks.ball_peak_von_mises_mpa) fix(value);
  fix(result.peaks.ball_peak_pressure_mpa);
  return finite;
}

}  // namespace hipfai::fem
