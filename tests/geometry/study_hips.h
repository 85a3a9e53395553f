// The generated study hips shared by the geometry tests of one test program: generation is the
// slow part, so each (ce, alpha, edge) is generated once per process (an inline function's
// static is one object across translation units).
#pragma once

#include "geometry/hip_generator.h"
#include "geometry/hip_measure.h"
#include "geometry/hip_model.h"

#include <map>
#include <tuple>

namespace hipfai::geometry::test_support {

// The thesis's surface levels (README "Parametric hips: resolution"): ~2 k and ~8 k vertices
// per model; the tests run the coarse ones, the fine ones are measured by the README command.
inline constexpr double kCoarsestEdgeMm = 7.0;
inline constexpr double kStudyTestEdgeMm = 3.0;

inline const HipModel& study_hip(double ce_deg, double alpha_deg, double edge_mm) {
  static std::map<std::tuple<double, double, double>, HipModel> cache;
  const auto key = std::make_tuple(ce_deg, alpha_deg, edge_mm);
  auto it = cache.find(key);
  if (it == cache.end()) {
    HipParameters p;
    p.ce_deg = ce_deg;
    p.alpha_deg = alpha_deg;
    p.edge_mm = edge_mm;
    it = cache.emplace(key, generate_hip(p).model).first;
  }
  return it->second;
}

struct MeasuredAngles {
  CeMeasurement ce;
  AlphaMeasurement alpha;
};

// CE and alpha measured on the model's meshes (bony acetabulum; femoral bone and cartilage).
inline MeasuredAngles measure_study_angles(const HipModel& model) {
  return {measure_ce_angle({&model.tissue("acetabular_bone"), &model.tissue("acetabular_cartilage")},
                           model.hjc_mm, model.lateral, model.superior),
          measure_alpha_angle({&model.tissue("femur_bone"), &model.tissue("femoral_cartilage")},
                              model.hjc_mm, model.neck_axis, model.superior, Vec3::UnitY())};
}

}  // namespace hipfai::geometry::test_support
