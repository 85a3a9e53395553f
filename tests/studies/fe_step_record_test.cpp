// The typed record of an FE step (studies/results/fe_step_record.h) and fe.csv read into it
// (studies/results/hip_fe_table.h): every measure comes from the column its names give, a missing column is
// a one-line error naming it, the names are one-to-one, and the validation study's columns keep
// their names.
#include "studies/results/fe_step_record.h"

#include "core/error.h"
#include "studies/results/hip_fe_table.h"
#include "studies/validation_study.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

// A small fe.csv: two steps, the tissues in `tissues` (in that column order), a column the record
// does not read between them, every number different. Its cells are the column's index plus
// 100 times the step, so a value tells which column it was read from.
struct SmallTable {
  std::vector<std::string> header;
  std::vector<FeTissue> tissues;
  std::string first_status = "0";  // the status cell of step 1 (step 2 did not converge)

  explicit SmallTable(std::vector<FeTissue> with) : tissues(std::move(with)) {
    header = {"step", "status", "dofs", "contact_area_mm2", "wall_time_s"};
    for (const PressureStat stat : kPressureStats) header.push_back(fe_csv_column(stat));
    for (const VonMisesStat stat : kVonMisesStats) {
      for (const FeTissue tissue : tissues) header.push_back(fe_csv_column(stat, tissue));
    }
    header.emplace_back("max_pressure_surface");
  }
  double cell(std::size_t step, const std::string& column) const {
    for (std::size_t c = 0; c < header.size(); ++c) {
      if (header[c] == column) return static_cast<double>(c) + 100.0 * static_cast<double>(step);
    }
    return std::numeric_limits<double>::quiet_NaN();
  }
  // The text without the column `drop` (none when empty).
  std::string csv(const std::string& drop = "") const {
    std::ostringstream out;
    const auto row = [&](const auto& value_of) {
      bool first = true;
      for (std::size_t c = 0; c < header.size(); ++c) {
        if (header[c] == drop) continue;
        out << (first ? "" : ",") << value_of(c);
        first = false;
      }
      out << '\n';
    };
    row([&](std::size_t c) { return header[c]; });
    for (std::size_t step = 1; step <= 2; ++step) {
      row([&](std::size_t c) -> std::string {
        if (header[c] == "status") return step == 1 ? first_status : "3";
        if (header[c] == "max_pressure_surface") return "labrum";
        return std::to_string(cell(step, header[c]));
      });
    }
    return out.str();
  }
};

HipFeTable parse(const std::string& text) {
  std::istringstream in(text);
  return parse_hip_fe_csv(in, "fe.csv");
}

TEST(FeStepRecord, ReadsEveryMeasureFromItsColumn) {
  // Labrum first: the tissues keep the table's order.
  const SmallTable written({FeTissue::kLabrum, FeTissue::kFemoralCartilage, FeTissue::kAcetabularCartilage});
  const HipFeTable table = parse(written.csv());
  EXPECT_EQ(table.tissues, written.tissues);
  ASSERT_EQ(table.steps.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const FeStepRecord& step = table.steps[k];
    EXPECT_EQ(step.status, k == 0 ? 0 : 3);
    EXPECT_EQ(step.converged(), k == 0);
    EXPECT_EQ(step.dofs, written.cell(k + 1, "dofs"));
    EXPECT_EQ(step.wall_time_s, written.cell(k + 1, "wall_time_s"));
    for (const PressureStat stat : kPressureStats) {
      EXPECT_EQ(step.pressure(stat), written.cell(k + 1, fe_csv_column(stat))) << to_string(stat);
    }
    for (const VonMisesStat stat : kVonMisesStats) {
      for (const FeTissue tissue : kFeTissues) {
        EXPECT_EQ(step.von_mises(stat, tissue), written.cell(k + 1, fe_csv_column(stat, tissue)))
            << to_string(stat) << ' ' << to_string(tissue);
      }
    }
  }
}

TEST(FeStepRecord, ATissueTheRunLacksIsNaN) {
  const HipFeTable table = parse(SmallTable({FeTissue::kFemoralCartilage, FeTissue::kLabrum}).csv());
  EXPECT_EQ(table.tissues, (std::vector<FeTissue>{FeTissue::kFemoralCartilage, FeTissue::kLabrum}));
  for (const VonMisesStat stat : kVonMisesStats) {
    EXPECT_TRUE(std::isnan(table.steps[0].von_mises(stat, FeTissue::kAcetabularCartilage)));
  }
}

TEST(FeStepRecord, AMissingColumnIsAOneLineErrorNamingIt) {
  const SmallTable written({FeTissue::kFemoralCartilage, FeTissue::kLabrum});
  for (const std::string& column : written.header) {
    if (column == "step" || column == "contact_area_mm2" || column == "max_pressure_surface") continue;  // not read
    try {
      (void)parse(written.csv(column));
      ADD_FAILURE() << column << ": read without it";
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("fe.csv: no column '" + column + "'"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

TEST(FeStepRecord, AStatusThatIsNotAWholeNumberIsAnError) {
  SmallTable written({FeTissue::kFemoralCartilage});
  written.first_status = "0.5";
  EXPECT_THROW((void)parse(written.csv()), Error);
  written.first_status = "converged";
  EXPECT_THROW((void)parse(written.csv()), Error);
}

TEST(FeStepRecord, NamesAreOneToOne) {
  std::set<std::string> tissues, bodies, fe_csv, outputs;
  for (const FeTissue tissue : kFeTissues) {
    tissues.insert(to_string(tissue));
    bodies.insert(fe_body_name(tissue));
  }
  EXPECT_EQ(tissues.size(), kFeTissues.size());
  EXPECT_EQ(bodies.size(), kFeTissues.size());
  std::size_t measures = 0;
  for (const PressureStat stat : kPressureStats) {
    fe_csv.insert(fe_csv_column(stat));
    outputs.insert(fe_measure_name(stat));
    ++measures;
  }
  for (const VonMisesStat stat : kVonMisesStats) {
    for (const FeTissue tissue : kFeTissues) fe_csv.insert(fe_csv_column(stat, tissue));
    outputs.insert(fe_measure_name(VonMisesMeasure{stat, std::nullopt}));
    for (const FeTissue tissue : kFeTissues) outputs.insert(fe_measure_name(VonMisesMeasure{stat, tissue}));
    measures += 1 + kFeTissues.size();
  }
  EXPECT_EQ(fe_csv.size(), kPressureStats.size() + kVonMisesStats.size() * kFeTissues.size());
  EXPECT_EQ(outputs.size(), measures);
  // The names the FE writes (studies/pipeline/hip_fe_run.cpp) and the studies' columns.
  EXPECT_EQ(fe_csv_column(VonMisesStat::kBall, FeTissue::kAcetabularCartilage),
            "ball_peak_von_mises_mpa acetabular cartilage");
  EXPECT_EQ(fe_csv_column(PressureStat::kMean), "mean_pressure_mpa");
  EXPECT_EQ(fe_measure_name(VonMisesMeasure{VonMisesStat::kP95, FeTissue::kFemoralCartilage}),
            "von_mises_p95_femoral_cartilage_mpa");
  EXPECT_EQ(fe_measure_name(PressureStat::kBall), "pressure_ball_mpa");
}

TEST(FeStepRecord, ValidationColumnsKeepTheirNames) {
  std::vector<std::string> names;
  for (const FeMeasure& measure : validation_fe_measures()) names.push_back(fe_measure_name(measure));
  EXPECT_EQ(names, (std::vector<std::string>{
                       "von_mises_ball_model_mpa", "von_mises_max_model_mpa", "von_mises_ball_labrum_mpa",
                       "von_mises_max_labrum_mpa", "von_mises_p95_labrum_mpa", "von_mises_ball_femoral_cartilage_mpa",
                       "von_mises_max_femoral_cartilage_mpa", "von_mises_p95_femoral_cartilage_mpa",
                       "von_mises_ball_acetabular_cartilage_mpa", "von_mises_max_acetabular_cartilage_mpa",
                       "von_mises_p95_acetabular_cartilage_mpa", "pressure_max_mpa", "pressure_ball_mpa",
                       "pressure_mean_mpa"}));
}

#ifdef HIPFAI_WITH_FEM
// The model's von Mises is the largest over the tissues the run has; a tissue it lacks reads 0; a
// step that did not converge is NaN in every measure.
TEST(FeStepRecord, ValidationMeasuresOfATable) {
  const SmallTable written({FeTissue::kFemoralCartilage, FeTissue::kLabrum});
  const HipFeTable table = parse(written.csv());
  const auto values = validation_fe_measures_of(table, 2, "fe.csv");
  const auto& measures = validation_fe_measures();
  ASSERT_EQ(values.size(), measures.size());
  for (std::size_t m = 0; m < measures.size(); ++m) {
    EXPECT_TRUE(std::isnan(values[m][1])) << fe_measure_name(measures[m]);
    double expected = 0.0;
    if (const auto* pressure = std::get_if<PressureStat>(&measures[m])) {
      expected = written.cell(1, fe_csv_column(*pressure));
    } else {
      const auto& von_mises = std::get<VonMisesMeasure>(measures[m]);
      for (const FeTissue tissue : written.tissues) {
        if (!von_mises.tissue || *von_mises.tissue == tissue) {
          expected = std::max(expected, written.cell(1, fe_csv_column(von_mises.stat, tissue)));
        }
      }
    }
    EXPECT_EQ(values[m][0], expected) << fe_measure_name(measures[m]);
  }
  EXPECT_THROW((void)validation_fe_measures_of(table, 3, "fe.csv"), Error);
}
#endif

}  // namespace
}  // namespace hipfai::studies
