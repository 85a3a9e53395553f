// The correlation report from a small synthetic validation folder with known correlations, and
// its handling of hips that never penetrate, constant FE measures, failed FE steps and bad files.
#include "studies/validation_report.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

std::filesystem::path fresh(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("hipfai_validation_report_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void write(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

// correlation.csv as rows of column -> text.
std::vector<std::map<std::string, std::string>> read_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) header.push_back(cell);
  }
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < header.size() && c < cells.size(); ++c) row[header[c]] = cells[c];
    rows.push_back(row);
  }
  return rows;
}

const std::map<std::string, std::string>* find_row(const std::vector<std::map<std::string, std::string>>& rows,
                                                  const std::string& ce, const std::string& alpha,
                                                  const std::string& depth, const std::string& measure) {
  for (const auto& row : rows) {
    if (row.at("ce_deg") == ce && row.at("alpha_deg") == alpha && row.at("depth") == depth &&
        row.at("measure") == measure) {
      return &row;
    }
  }
  return nullptr;
}

// Hip CE 40 / alpha 60: curvilinear depth x = 1..5 against the primary measure y = (2, 4, 5, 4, 5):
// r = 0.6 / sqrt(0.6) = sqrt(0.6) (Sxy = 6, Sxx = 10, Syy = 6), and against pressure 3x + 1 (r = 1);
// radial depth 0 at every step (n.p.); p95 labrum constant. Hip CE 20 / alpha 40: no penetration;
// its third FE step did not converge (empty cells).
std::string synthetic_steps() {
  std::ostringstream csv;
  csv << "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm,von_mises_ball_model_mpa,"
         "von_mises_p95_labrum_mpa,pressure_max_mpa\n";
  const double y[] = {2, 4, 5, 4, 5};
  for (int k = 0; k < 5; ++k) {
    const double x = k + 1;
    csv << "40,60," << k + 1 << ',' << 12.0 * (k + 1) << ',' << x << ",0," << y[k] << ",1.5," << 3 * x + 1 << '\n';
  }
  for (int k = 0; k < 5; ++k) {
    csv << "20,40," << k + 1 << ',' << 12.0 * (k + 1) << ",0,0,";
    if (k == 2) csv << ",,\n";
    else csv << 0.1 * (k + 1) << ",0.2," << 0.3 * (k + 1) << '\n';
  }
  return csv.str();
}

TEST(ValidationReport, CorrelationsOfASyntheticSetMatchTheirClosedForms) {
  const auto dir = fresh("synthetic");
  write(dir / "steps.csv", synthetic_steps());
  const CorrelationReportResult result = write_correlation_report(dir);
  const auto rows = read_csv(dir / "correlation.csv");
  ASSERT_EQ(rows.size(), 2u * 2u * 3u);  // hips x depths x measures

  const auto* primary = find_row(rows, "40", "60", "curvilinear", "von_mises_ball_model_mpa");
  ASSERT_NE(primary, nullptr);
  EXPECT_EQ(primary->at("status"), "ok");
  EXPECT_EQ(primary->at("n"), "5");
  EXPECT_NEAR(std::stod(primary->at("r")), std::sqrt(0.6), 1e-9);
  const auto* linear = find_row(rows, "40", "60", "curvilinear", "pressure_max_mpa");
  ASSERT_NE(linear, nullptr);
  EXPECT_NEAR(std::stod(linear->at("r")), 1.0, 1e-12);
  EXPECT_EQ(find_row(rows, "40", "60", "radial", "von_mises_ball_model_mpa")->at("status"), "n.p.");
  EXPECT_EQ(find_row(rows, "40", "60", "curvilinear", "von_mises_p95_labrum_mpa")->at("status"), "constant");
  const auto* never = find_row(rows, "20", "40", "curvilinear", "von_mises_ball_model_mpa");
  EXPECT_EQ(never->at("status"), "n.p.");
  EXPECT_EQ(never->at("n"), "4");  // the failed FE step is left out
  EXPECT_EQ(never->at("r"), "");

  // The summary counts the one correlated cell of the primary measure.
  EXPECT_EQ(result.ok_cells, 1);
  EXPECT_NEAR(result.mean_r_curvilinear, std::sqrt(0.6), 1e-9);

  std::ifstream in(dir / "report.md");
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(md.find("## Table 8"), std::string::npos);
  EXPECT_NE(md.find("## Table 9"), std::string::npos);
  // Our r beside the thesis' (CE 40 / alpha 60, Table 8: 0.93, 4.15e-12) and their difference.
  EXPECT_NE(md.find("0.77, "), std::string::npos);
  EXPECT_NE(md.find("thesis 0.93, 4.15e-12"), std::string::npos);
  EXPECT_NE(md.find("Δr -0.16"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "fig60_ce40_alpha60.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "rmap_curvilinear.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "scatter_radial.svg"));
}

TEST(ValidationReport, RejectsMalformedFilesWithTheirLine) {
  const auto dir = fresh("bad");
  EXPECT_THROW(write_correlation_report(dir), Error);  // no steps.csv
  write(dir / "steps.csv", "ce_deg,alpha_deg,step,angle,max_curvilinear_mm,max_radial_mm\n");
  try {
    write_correlation_report(dir);
    FAIL() << "a wrong header was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("steps.csv:1"), std::string::npos) << error.what();
  }
  write(dir / "steps.csv",
        "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm,von_mises_ball_model_mpa\n"
        "40,60,1,10,0.5,zero,1\n");
  try {
    write_correlation_report(dir);
    FAIL() << "a malformed number was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("steps.csv:2"), std::string::npos) << error.what();
  }
  write(dir / "steps.csv", "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm,stress\n");
  EXPECT_THROW(write_correlation_report(dir), Error);  // not an FE measure column
  EXPECT_FALSE(std::filesystem::exists(dir / "report.md"));
}

// Leave-one-out: two well separated clusters of hips are classified correctly, and a hip alone in
// its class can never be assigned its own class (its rule never sees it).
TEST(ValidationReport, LeaveOneOutNeverUsesTheHipItClassifies) {
  ValidationData data;
  data.measures = {"von_mises_ball_model_mpa"};
  auto hip = [](double ce, double alpha, double c, double r) {
    ValidationHipSeries h;
    h.ce_deg = ce, h.alpha_deg = alpha;
    h.angle_deg = {10, 20, 30};
    h.curvilinear_mm = {0, c / 2, c};
    h.radial_mm = {0, r / 2, r};
    h.fe = {{1, 2, 3}};
    return h;
  };
  data.hips = {hip(40, 80, 20, 9), hip(40, 70, 19, 8.5),  // combined cam-pincer
               hip(20, 80, 15, 10), hip(20, 70, 14, 9.8),  // cam
               hip(40, 40, 6, 0)};                          // the only pincer
  const ValidationClassification result = classify_leave_one_out(data);
  ASSERT_EQ(result.assigned.size(), 5u);
  EXPECT_EQ(result.assigned[0], "combined cam-pincer");
  EXPECT_EQ(result.assigned[1], "combined cam-pincer");
  EXPECT_EQ(result.assigned[2], "cam");
  EXPECT_EQ(result.assigned[3], "cam");
  EXPECT_NE(result.assigned[4], "pincer");
  EXPECT_EQ(result.correct, 4);
}

}  // namespace
}  // namespace hipfai::studies
