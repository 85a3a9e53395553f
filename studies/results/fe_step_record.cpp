// hipfai — the names of an FE step's measures (see fe_step_record.h): one table per enum, indexed
// by it, with the name fe.csv uses and the name the studies' outputs use.
#include "studies/results/fe_step_record.h"

namespace hipfai::studies {
namespace {

// A name in the FE run's table (studies/pipeline/hip_fe_run.cpp, write_hip_fe_csv) and in the studies'
// output columns.
struct Names {
  const char* fe_csv;
  const char* output;
};

// [FeTissue]: the FE body's name, the tissue's name.
constexpr std::array<Names, kFeTissues.size()> kTissueNames{{
    {"femoral cartilage", "femoral_cartilage"},
    {"acetabular cartilage", "acetabular_cartilage"},
    {"labrum", "labrum"},
}};

// [VonMisesStat]: the column's name before the body's, the statistic's word.
constexpr std::array<Names, kVonMisesStats.size()> kVonMisesNames{{
    {"max_von_mises_mpa", "max"},
    {"ball_peak_von_mises_mpa", "ball"},
    {"p95_von_mises_mpa", "p95"},
}};

// [PressureStat]: the column's name, the statistic's word.
constexpr std::array<Names, kPressureStats.size()> kPressureNames{{
    {"max_pressure_mpa", "max"},
    {"mean_pressure_mpa", "mean"},
    {"ball_peak_pressure_mpa", "ball"},
}};

template <class Enum, std::size_t N>
const Names& names_of(const std::array<Names, N>& table, Enum value) {
  return table[static_cast<std::size_t>(value)];
}

}  // namespace

const char* to_string(FeTissue tissue) { return names_of(kTissueNames, tissue).output; }
const char* to_string(VonMisesStat stat) { return names_of(kVonMisesNames, stat).output; }
const char* to_string(PressureStat stat) { return names_of(kPressureNames, stat).output; }
const char* fe_body_name(FeTissue tissue) { return names_of(kTissueNames, tissue).fe_csv; }

std::string fe_csv_column(VonMisesStat stat, FeTissue tissue) {
  return std::string(names_of(kVonMisesNames, stat).fe_csv) + ' ' + fe_body_name(tissue);
}

std::string fe_csv_column(PressureStat stat) { return names_of(kPressureNames, stat).fe_csv; }

std::string fe_measure_name(const FeMeasure& measure) {
  if (const auto* pressure = std::get_if<PressureStat>(&measure)) {
    return std::string("pressure_") + to_string(*pressure) + "_mpa";
  }
  const auto& von_mises = std::get<VonMisesMeasure>(measure);
  return std::string("von_mises_") + to_string(von_mises.stat) + '_' +
         (von_mises.tissue ? to_string(*von_mises.tissue) : "model") + "_mpa";
}

}  // namespace hipfai::studies
