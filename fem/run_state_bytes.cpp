#include "fem/run_state_bytes.h"

#include <type_traits>

namespace hipfai::fem {

namespace {

static_assert(std::is_trivially_copyable_v<SolveStatistics>);
static_assert(std::is_trivially_copyable_v<ContactNode>);

// Each function lists a structure's fields once, for writing (Bytes = ByteWriter, a const
// structure) and reading (ByteReader) alike; a size is written from the structure and read into
// it, which then resizes.

// Each field in turn.
template <class Bytes, class... Fields>
void transfer_fields(Bytes& bytes, Fields&... fields) {
  (bytes.io(fields), ...);
}

template <class Bytes, class Peaks>
void transfer_peaks(Bytes& bytes, Peaks& peaks) {
  transfer_fields(bytes, peaks.max_penetration_mm, peaks.contact_area_mm2, peaks.max_pressure_mpa,
                  peaks.mean_pressure_mpa, peaks.max_von_mises_mpa, peaks.p95_von_mises_mpa,
                  peaks.peak_average_radius_mm, peaks.ball_peak_von_mises_mpa,
                  peaks.ball_peak_von_mises_position_mm, peaks.ball_peak_pressure_mpa,
                  peaks.ball_peak_pressure_position_mm, peaks.max_pressure_position_mm,
                  peaks.max_pressure_pair, peaks.ball_peak_pressure_pair);
}

template <class Bytes, class State>
void transfer_run_state(Bytes& bytes, State& state) {
  transfer_fields(bytes, state.result.status, state.result.statistics, state.result.nodes,
                  state.result.pair_force_n, state.result.rigid_translation_mm);
  transfer_peaks(bytes, state.result.peaks);
}

}  // namespace

void write_run_state(const RunState& state, ByteWriter& out) { transfer_run_state(out, state); }

RunState read_run_state(ByteReader& in) {
  RunState state;
  transfer_run_state(in, state);
  return state;
}

}  // namespace hipfai::fem
