// The six characteristic morphologies of thesis Table 10, generated at a test-suite resolution
// (3 mm edges, 10 sub-motions of standing to sitting): what penetrates, what does not, and that
// every one starts apart (no penetration in the neutral pose). A generator change that loses the
// cam, moves it off the rim's path or lets the bodies overlap at the start fails here.
#include "geometry/hip_generator.h"
#include "studies/fai_reference.h"
#include "studies/hip_sensitivity.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/penetration_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace hipfai::studies {
namespace {

constexpr double kEdgeMm = 3.0;

struct Outcome {
  PenetrationRun motion;   // standing to sitting, 10 sub-motions
  PenetrationRun neutral;  // the neutral pose alone
  double first_contact_deg = 0.0;
};


const Outcome& outcome(double ce, double alpha) {
  static std::map<std::pair<double, double>, Outcome> cache;
  auto it = cache.find({ce, alpha});
  if (it != cache.end()) return it->second;
  geometry::HipParameters p;
  p.ce_deg = ce;
  p.alpha_deg = alpha;
  p.edge_mm = kEdgeMm;
  const geometry::HipModel model = geometry::generate_hip(p).model;
  const LoadedHip hip = loaded_hip_from_model(model, "morphology");
  Outcome o;
  StageLog log;
  const Motion motion = standing_to_sitting(10);
  o.motion = compute_penetration(hip, motion, {}, log);
  Motion neutral;
  neutral.steps.push_back(make_step(geometry::HipPoseDeg{0.0, 0.0, 0.0}));
  o.neutral = compute_penetration(hip, neutral, {}, log);
  o.first_contact_deg = first_striking_contact_deg(model.tissue("femur_bone"), model.tissue("labrum"), model.hjc_mm,
                                                   (hip.frame * motion.steps.front().axis).normalized(),
                                                   p.articular_radius_mm + o.motion.contact_tolerance_mm, 2);
  return cache.emplace(std::make_pair(ce, alpha), std::move(o)).first->second;
}

class Morphology : public ::testing::TestWithParam<ReferenceMorphology> {};

TEST_P(Morphology, StartsApart) {
  const Outcome& o = outcome(GetParam().ce_deg, GetParam().alpha_deg);
  EXPECT_EQ(o.neutral.max_curvilinear_mm(), 0.0);
  EXPECT_EQ(o.neutral.max_radial_mm(), 0.0);
  EXPECT_GT(o.first_contact_deg, 0.5);
}

INSTANTIATE_TEST_SUITE_P(ThesisTable10, Morphology, ::testing::ValuesIn(thesis_table10()),
                         [](const auto& test_info) {
                           std::string name = test_info.param.name;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

// The thesis' outcome for the normal and dysplastic hips (no penetration), for the cam hips (both
// depths) and the depth order of its Table 10 (combined deeper than pure cam, curvilinear).
TEST(MorphologyOutcome, NormalAndDysplasticStayClearCamHipsImpinge) {
  for (const auto& [ce, alpha] : {std::pair{20.0, 40.0}, std::pair{0.0, 40.0}}) {
    const Outcome& o = outcome(ce, alpha);
    EXPECT_EQ(o.motion.max_curvilinear_mm(), 0.0) << "CE " << ce << " alpha " << alpha;
    EXPECT_EQ(o.motion.max_radial_mm(), 0.0) << "CE " << ce << " alpha " << alpha;
    EXPECT_GT(o.first_contact_deg, standing_to_sitting(10).steps.back().angle_deg);
  }
  const Outcome& cam = outcome(20, 80);
  const Outcome& combined = outcome(40, 80);
  const double motion_deg = standing_to_sitting(10).steps.back().angle_deg;
  for (const Outcome* o : {&cam, &combined}) {
    EXPECT_GT(o->motion.max_curvilinear_mm(), 1.0);
    EXPECT_GT(o->motion.max_radial_mm(), 1.0);
    EXPECT_LT(o->first_contact_deg, motion_deg);
  }
  EXPECT_GT(combined.motion.max_curvilinear_mm(), cam.motion.max_curvilinear_mm());
  EXPECT_LT(combined.first_contact_deg, cam.first_contact_deg);
  // The pincer socket (CE 40) meets the femur radially (its deep rim over the head-neck junction).
  EXPECT_GT(outcome(40, 40).motion.max_radial_mm(), 0.0);
}

}  // namespace
}  // namespace hipfai::studies
