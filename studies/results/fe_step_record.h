// hipfai — one FE step's measures as a typed record: the peak von Mises stresses of each tissue
// and the contact pressures of a row of an FE run's per-step table (fe.csv, studies/results/hip_fe_table.h),
// and the measures the studies report from them.
//
// The tissues and the kinds of measure are enums with one table of names each (fe_step_record.cpp):
// the fe.csv column names ("max_von_mises_mpa femoral cartilage", "ball_peak_pressure_mpa") and the
// studies' output column names ("von_mises_max_femoral_cartilage_mpa", "pressure_ball_mpa") are
// both made from them there, so that no reader builds or takes apart a column name. Free of the FE
// module, like the table it is read from.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <variant>

namespace hipfai::studies {

// The deformable bodies of the hip FE model (fem/hip_fe_model.h), in the order the model lists
// them. A run may lack the acetabular cartilage or the labrum.
enum class FeTissue { kFemoralCartilage, kAcetabularCartilage, kLabrum };
inline constexpr std::array<FeTissue, 3> kFeTissues{FeTissue::kFemoralCartilage, FeTissue::kAcetabularCartilage,
                                                    FeTissue::kLabrum};

// Statistics of a tissue's von Mises stress in a step: the largest at a Gauss point, the largest
// average over a ball about a peak (fem/peak_measures.h) and the 95th percentile. Enum order is the
// column order of a scene's steps.csv.
enum class VonMisesStat { kMax, kBall, kP95 };
inline constexpr std::array<VonMisesStat, 3> kVonMisesStats{VonMisesStat::kMax, VonMisesStat::kBall,
                                                            VonMisesStat::kP95};

// Statistics of the contact pressure in a step: the largest, the mean over the contact area and
// the largest average over a ball about a peak. Enum order is the column order of a scene's
// steps.csv.
enum class PressureStat { kMax, kMean, kBall };
inline constexpr std::array<PressureStat, 3> kPressureStats{PressureStat::kMax, PressureStat::kMean,
                                                            PressureStat::kBall};

// The names in the studies' output columns: "femoral_cartilage"; "max", "ball", "p95"; "max",
// "mean", "ball".
const char* to_string(FeTissue tissue);
const char* to_string(VonMisesStat stat);
const char* to_string(PressureStat stat);
// The FE model's name of a tissue ("femoral cartilage"): the body in fe.csv's column names.
const char* fe_body_name(FeTissue tissue);
// fe.csv's column of a statistic: "max_von_mises_mpa femoral cartilage", "ball_peak_pressure_mpa".
std::string fe_csv_column(VonMisesStat stat, FeTissue tissue);
std::string fe_csv_column(PressureStat stat);

// One step of an FE run, as its fe.csv row has it.
struct FeStepRecord {
  int status = 0;           // fem::ContactStatus code: 0 converged, else why not
  double wall_time_s = 0.0; // the step's solve time when it was computed
  double dofs = 0.0;        // degrees of freedom of the model (a count, kept as the table's number)
  // [VonMisesStat][FeTissue], MPa; NaN for a tissue the run does not have, and where the table's
  // cell is not a number.
  std::array<std::array<double, kFeTissues.size()>, kVonMisesStats.size()> von_mises_mpa{};
  std::array<double, kPressureStats.size()> pressure_mpa{};  // [PressureStat], MPa; NaN as above

  bool converged() const { return status == 0; }
  double von_mises(VonMisesStat stat, FeTissue tissue) const {
    return von_mises_mpa[static_cast<std::size_t>(stat)][static_cast<std::size_t>(tissue)];
  }
  double pressure(PressureStat stat) const { return pressure_mpa[static_cast<std::size_t>(stat)]; }
};

// A von Mises measure as the studies report it: a statistic of one tissue, or of the whole model
// (no tissue: the largest over the model's tissues).
struct VonMisesMeasure {
  VonMisesStat stat = VonMisesStat::kMax;
  std::optional<FeTissue> tissue;  // empty: the model
  bool operator==(const VonMisesMeasure&) const = default;
};

// A measure of an FE step that the studies write as a column: von Mises or contact pressure.
using FeMeasure = std::variant<VonMisesMeasure, PressureStat>;

// The output column name of a measure: "von_mises_<stat>_<tissue|model>_mpa", "pressure_<stat>_mpa".
std::string fe_measure_name(const FeMeasure& measure);

}  // namespace hipfai::studies
