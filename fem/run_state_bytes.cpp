#include "fem/run_state_bytes.h"

#include <type_traits>

namespace hipfai::fem {

namespace {

static_assert(std::is_trivially_copyable_v<SolveStatistics>);
static_assert(std::is_trivially_copyable_v<ContactNode>);
static_assert(std::is_trivially_copyable_v<dealii::Point<3>>);

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

template <class Bytes, class Node>
void transfer_node(Bytes& bytes, Node& node) {
  transfer_fields(bytes, node.pair, node.dofs, node.constrained_component, node.position,
                  node.normal, node.initial_gap, node.area, node.rigid_body);
  for (auto& weights : node.master) {  // (dof, weight) pairs: std::pair is not trivially copyable
    std::size_t n = weights.size();
    bytes.io(n);
    if constexpr (!std::is_const_v<Node>) weights.resize(n);
    for (auto& [dof, weight] : weights) {
      bytes.io(dof);
      bytes.io(weight);
    }
  }
}

template <class Bytes, class Values>
void transfer_dealii_vector(Bytes& bytes, Values& values) {
  std::size_t n = values.size();
  bytes.io(n);
  if constexpr (!std::is_const_v<Values>) values.reinit(n);
  bytes.io_array(values.data(), n);
}

template <class Bytes, class State>
void transfer_run_state(Bytes& bytes, State& state) {
  constexpr bool reading = !std::is_const_v<State>;
  transfer_fields(bytes, state.result.status, state.result.statistics, state.result.nodes,
                  state.result.pair_force_n, state.result.rigid_translation_mm);
  transfer_peaks(bytes, state.result.peaks);
  transfer_dealii_vector(bytes, state.displacement);
  transfer_dealii_vector(bytes, state.cell_von_mises);
  std::size_t n_nodes = state.nodes.size();
  bytes.io(n_nodes);
  if constexpr (reading) state.nodes.resize(n_nodes);
  for (auto& node : state.nodes) transfer_node(bytes, node);
  transfer_fields(bytes, state.fields.pressure_mpa, state.fields.gap_mm);
  std::vector<char> active(state.fields.active.begin(), state.fields.active.end());
  bytes.io(active);
  if constexpr (reading) state.fields.active.assign(active.begin(), active.end());
}

}  // namespace

void write_run_state(const RunState& state, ByteWriter& out) { transfer_run_state(out, state); }

RunState read_run_state(ByteReader& in) {
  RunState state;
  transfer_run_state(in, state);
  return state;
}

}  // namespace hipfai::fem
