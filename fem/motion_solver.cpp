#include "fem/motion_solver.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

namespace hipfai::fem {

dealii::Tensor<2, 3> rotation_about_axis(const dealii::Tensor<1, 3>& axis_in, double angle_rad) {
  const dealii::Tensor<1, 3> axis = axis_in / axis_in.norm();
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  dealii::Tensor<2, 3> rotation;
  for (unsigned i = 0; i < 3; ++i) {
    for (unsigned j = 0; j < 3; ++j) rotation[i][j] = (i == j ? c : 0.0) + (1 - c) * axis[i] * axis[j];
  }
  // + s [axis]_x (cross-product matrix)
  rotation[0][1] -= s * axis[2];
  rotation[0][2] += s * axis[1];
  rotation[1][0] += s * axis[2];
  rotation[1][2] -= s * axis[0];
  rotation[2][0] -= s * axis[1];
  rotation[2][1] += s * axis[0];
  return rotation;
}

namespace {

// Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd: branch on the largest of the
// four squared components, so no division by a small number).
std::array<double, 4> to_quaternion(const dealii::Tensor<2, 3>& r) {
  const double trace = r[0][0] + r[1][1] + r[2][2];
  std::array<double, 4> q{};
  if (trace >= r[0][0] && trace >= r[1][1] && trace >= r[2][2]) {
    const double w = 0.5 * std::sqrt(1.0 + trace);
    q = {w, (r[2][1] - r[1][2]) / (4 * w), (r[0][2] - r[2][0]) / (4 * w), (r[1][0] - r[0][1]) / (4 * w)};
  } else {
    unsigned i = 0;
    if (r[1][1] > r[i][i]) i = 1;
    if (r[2][2] > r[i][i]) i = 2;
    const unsigned j = (i + 1) % 3, k = (i + 2) % 3;
    const double v = 0.5 * std::sqrt(1.0 + r[i][i] - r[j][j] - r[k][k]);
    q[0] = (r[k][j] - r[j][k]) / (4 * v);
    q[1 + i] = v;
    q[1 + j] = (r[j][i] + r[i][j]) / (4 * v);
    q[1 + k] = (r[k][i] + r[i][k]) / (4 * v);
  }
  return q;
}

// Counters of a failed attempt, added to the step's totals.
void add_effort(ContactResult& total, const ContactResult& attempt) {
  total.statistics.active_set_iterations += attempt.statistics.active_set_iterations;
  total.statistics.linear_solves += attempt.statistics.linear_solves;
  total.statistics.rank_columns += attempt.statistics.rank_columns;
  total.statistics.linear_iterations += attempt.statistics.linear_iterations;
  total.statistics.factorisations += attempt.statistics.factorisations;
  total.statistics.low_rank_updates += attempt.statistics.low_rank_updates;
  total.statistics.wall_time_s += attempt.statistics.wall_time_s;
}

// Steps whose contact is searched ahead (each holds its contact nodes, ~5 MB at default).
constexpr std::size_t kStepsSearchedAhead = 32;

struct State {
  dealii::Tensor<2, 3> rotation;
  dealii::Tensor<1, 3> force_n;
  dealii::Tensor<1, 3> translation_mm;
};

class CutbackSolver {
 public:
  CutbackSolver(ContactProblem& problem, unsigned int body, unsigned int max_depth, bool search_ahead)
      : problem_(problem), body_(body), max_depth_(max_depth), search_ahead_(search_ahead) {}

  // Solves `target` starting from the converged `from`; on success `from` becomes the target's
  // converged state. Returns the last attempt with the effort of all attempts summed. `next`:
  // the rotations of the steps after, whose contact searches run beside the solves.
  ContactResult solve(State& from, const MotionStep& target, const std::vector<dealii::Tensor<2, 3>>& next) {
    ContactResult effort;  // only its counters are used
    effort.statistics.sub_steps = 0;
    ContactResult last = attempt(from, target, 0, effort, next);
    last.statistics.active_set_iterations = effort.statistics.active_set_iterations;
    last.statistics.linear_solves = effort.statistics.linear_solves;
    last.statistics.rank_columns = effort.statistics.rank_columns;
    last.statistics.linear_iterations = effort.statistics.linear_iterations;
    last.statistics.factorisations = effort.statistics.factorisations;
    last.statistics.low_rank_updates = effort.statistics.low_rank_updates;
    last.statistics.wall_time_s = effort.statistics.wall_time_s;
    last.statistics.sub_steps = effort.statistics.sub_steps;
    last.statistics.cutbacks = effort.statistics.cutbacks;
    return last;
  }

 private:
  // `after`: the rotations of the runs that follow if this one converges.
  ContactResult attempt(State& from, const MotionStep& target, unsigned int depth, ContactResult& effort,
                        const std::vector<dealii::Tensor<2, 3>>& after) {
    RigidBody& body = problem_.model().rigid_bodies[body_];
    body.rotation = target.rotation;
    body.force_n = target.force_n;
    body.translation_mm = from.translation_mm;
    if (search_ahead_) {
      std::vector<ContactModel> upcoming(after.size(), problem_.model());
      for (std::size_t k = 0; k < after.size(); ++k) upcoming[k].rigid_bodies[body_].rotation = after[k];
      problem_.expect_next(std::move(upcoming));
    }
    ContactResult result = problem_.run();
    add_effort(effort, result);
    // ContactProblem::run checks every number it returns (kNonFinite otherwise).
    if (result.status == ContactStatus::kConverged) {
      ++effort.statistics.sub_steps;
      from = {target.rotation, target.force_n, result.rigid_translation_mm[body_]};
      return result;
    }
    if (depth >= max_depth_) {
      ++effort.statistics.sub_steps;
      return result;
    }
    ++effort.statistics.cutbacks;
    const MotionStep middle{interpolate_rotation(from.rotation, target.rotation, 0.5),
                            0.5 * (from.force_n + target.force_n)};
    std::vector<dealii::Tensor<2, 3>> after_half = {target.rotation};
    after_half.insert(after_half.end(), after.begin(), after.end());
    ContactResult half = attempt(from, middle, depth + 1, effort, after_half);
    if (half.status != ContactStatus::kConverged) return half;
    return attempt(from, target, depth + 1, effort, after);
  }

  ContactProblem& problem_;
  unsigned int body_;
  unsigned int max_depth_;
  bool search_ahead_;
};

// ParaView collection of the written steps, the step number as time.
void write_pvd(const std::string& prefix, const std::vector<std::pair<double, std::string>>& files) {
  write_file_atomically(prefix + ".pvd",
                        [&files](std::ostream& out) { dealii::DataOutBase::write_pvd_record(out, files); });
}

}  // namespace

dealii::Tensor<2, 3> interpolate_rotation(const dealii::Tensor<2, 3>& from, const dealii::Tensor<2, 3>& to,
                                          double s) {
  // Relative rotation from^T to, as axis and angle in [0, pi]; the shortest arc is s of it.
  const std::array<double, 4> q = to_quaternion(dealii::transpose(from) * to);
  const double sine = std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  double angle = 2.0 * std::atan2(sine, std::abs(q[0]));  // |w|: the shorter of q and -q
  if (!(sine > 0.0)) return from;
  const double sign = q[0] < 0.0 ? -1.0 : 1.0;
  const dealii::Tensor<1, 3> axis({sign * q[1] / sine, sign * q[2] / sine, sign * q[3] / sine});
  angle *= s;
  return from * rotation_about_axis(axis, angle);
}

std::vector<ContactResult> run_motion(
    ContactProblem& problem, const std::vector<MotionStep>& steps, const MotionOptions& options,
    const std::function<void(std::size_t, const ContactResult&)>& on_step) {
  if (options.moving_body >= problem.model().rigid_bodies.size()) {
    throw_error("fem motion: moving body ", options.moving_body, " does not exist (",
                problem.model().rigid_bodies.size(), " rigid bodies)");
  }
  if (options.vtu_every > 0 && options.vtu_prefix.empty()) {
    throw_error("fem motion: VTU output every ", options.vtu_every, " steps needs a file prefix");
  }
  RigidBody& body = problem.model().rigid_bodies[options.moving_body];
  body.load_controlled = true;
  body.free_directions = options.free_directions;
  if (body.free_directions.empty()) {
    body.free_directions = {dealii::Tensor<1, 3>({1, 0, 0}), dealii::Tensor<1, 3>({0, 1, 0}),
                            dealii::Tensor<1, 3>({0, 0, 1})};
  }
  // The last converged state: the body as given before the first step.
  State converged{body.rotation, body.force_n, body.translation_mm};
  CutbackSolver solver(problem, options.moving_body, options.max_cutback_depth, options.search_ahead);
  const bool rank0 = dealii::Utilities::MPI::this_mpi_process(problem.communicator()) == 0;
  std::vector<std::pair<double, std::string>> vtu_files;
  std::vector<ContactResult> results;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    // The searches of the next steps run beside this one's solve: the first step's compliance
    // columns leave time for many; a few steps ahead keep their memory small.
    std::vector<dealii::Tensor<2, 3>> next;
    for (std::size_t j = k + 1; j < std::min(steps.size(), k + 1 + kStepsSearchedAhead); ++j)
      next.push_back(steps[j].rotation);
    results.push_back(solver.solve(converged, steps[k], next));
    const bool last = k + 1 == steps.size();
    if (options.vtu_every > 0 && ((k + 1) % options.vtu_every == 0 || last)) {
      const std::string file = options.vtu_prefix + "_" + std::to_string(k + 1) + ".vtu";
      problem.write_vtu(file);
      // The .pvd sits beside the .vtu files and names them relative to itself.
      vtu_files.emplace_back(static_cast<double>(k + 1), std::filesystem::path(file).filename().string());
      if (rank0) write_pvd(options.vtu_prefix, vtu_files);
      // Every rank returns with the collection on disk (callers may read it at once).
      MPI_Barrier(problem.communicator());
    }
    if (on_step) on_step(k, results.back());
  }
  return results;
}

}  // namespace hipfai::fem
