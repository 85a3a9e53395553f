// fem::summarize_contact, summarize_stress and make_finite on synthetic nodes and samples, and
// the result's status names.
#include "fem/contact_summary.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hipfai::fem {
namespace {

using dealii::Point;
using dealii::Tensor;

SlaveNode node_at(unsigned int pair, const Point<3>& position, double area, double initial_gap) {
  SlaveNode node;
  node.pair = pair;
  node.position = position;
  node.normal = Tensor<1, 3>({0, 0, 1});
  node.area = area;
  node.initial_gap = initial_gap;
  return node;
}

TEST(FemContactSummary, SummarisesTheActiveNodes) {
  const std::vector<SlaveNode> nodes = {node_at(0, Point<3>(0, 0, 0), 1.0, 0.0),
                                        node_at(1, Point<3>(10, 0, 0), 2.0, 0.0),
                                        node_at(1, Point<3>(20, 0, 0), 1.0, 0.3)};
  const std::vector<bool> active = {true, true, false};
  const std::vector<double> force = {3.0, 2.0, 5.0}, gap = {0.0, -0.01, 0.2};
  ContactResult result;
  summarize_contact(nodes, active, force, gap, 2, 1.0, result);
  ASSERT_EQ(result.nodes.size(), 3u);
  EXPECT_DOUBLE_EQ(result.nodes[0].pressure_mpa, 3.0);
  EXPECT_DOUBLE_EQ(result.nodes[1].pressure_mpa, 1.0);
  EXPECT_DOUBLE_EQ(result.nodes[2].force_n, 0.0);  // inactive: no force
  EXPECT_DOUBLE_EQ(result.peaks.contact_area_mm2, 3.0);
  EXPECT_DOUBLE_EQ(result.peaks.mean_pressure_mpa, 5.0 / 3.0);
  EXPECT_DOUBLE_EQ(result.peaks.max_pressure_mpa, 3.0);
  EXPECT_EQ(result.peaks.max_pressure_pair, 0);
  EXPECT_DOUBLE_EQ(result.peaks.max_penetration_mm, 0.01);
  ASSERT_EQ(result.pair_force_n.size(), 2u);
  EXPECT_DOUBLE_EQ(result.pair_force_n[1][2], 2.0);
  // Balls of 1 mm hold one node each: the peak is the largest pressure.
  EXPECT_DOUBLE_EQ(result.peaks.ball_peak_pressure_mpa, 3.0);
  EXPECT_EQ(result.peaks.ball_peak_pressure_pair, 0);
  EXPECT_DOUBLE_EQ(result.peaks.peak_average_radius_mm, 1.0);
}

TEST(FemContactSummary, NoSolvedStateKeepsTheInitialGaps) {
  const std::vector<SlaveNode> nodes = {node_at(0, Point<3>(0, 0, 0), 1.0, 0.25)};
  ContactResult result;
  summarize_contact(nodes, {true}, {}, {}, 1, 1.0, result);
  EXPECT_DOUBLE_EQ(result.nodes[0].gap_mm, 0.25);
  EXPECT_DOUBLE_EQ(result.nodes[0].force_n, 0.0);
  EXPECT_EQ(result.peaks.ball_peak_pressure_pair, 0);
}

TEST(FemContactSummary, StressPercentilesAndPeaksPerBody) {
  VonMisesField field;
  field.samples.resize(2);
  for (int i = 1; i <= 20; ++i)
    field.samples[0].push_back({geometry::Vec3(i * 10.0, 0, 0), double(i), 1.0});
  ContactResult result;
  summarize_stress(field, 1.0, result);
  ASSERT_EQ(result.peaks.max_von_mises_mpa.size(), 2u);
  EXPECT_DOUBLE_EQ(result.peaks.max_von_mises_mpa[0], 20.0);
  EXPECT_DOUBLE_EQ(result.peaks.p95_von_mises_mpa[0], 19.0);  // nearest rank: the 19th of 20
  EXPECT_DOUBLE_EQ(result.peaks.ball_peak_von_mises_mpa[0], 20.0);
  EXPECT_DOUBLE_EQ(result.peaks.ball_peak_von_mises_position_mm[0][0], 200.0);
  EXPECT_DOUBLE_EQ(result.peaks.max_von_mises_mpa[1], 0.0);  // no samples
}

TEST(FemContactSummary, MakeFiniteZeroesNonFiniteNumbers) {
  ContactResult result;
  result.nodes.resize(1);
  dealii::Vector<double> displacement(2);
  EXPECT_TRUE(make_finite(result, displacement));
  result.peaks.max_pressure_mpa = std::numeric_limits<double>::quiet_NaN();
  displacement[1] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(make_finite(result, displacement));
  EXPECT_EQ(result.peaks.max_pressure_mpa, 0.0);
  EXPECT_EQ(displacement[1], 0.0);
  EXPECT_STREQ(to_string(ContactStatus::kNonFinite), "non-finite numbers");
  EXPECT_STREQ(to_string(ContactStatus::kConverged), "converged");
}

}  // namespace
}  // namespace hipfai::fem
