#include "fem/contact_problem.h"

#include "core/error.h"
#include "fem/active_set_strategy.h"
#include "fem/body_compliance.h"
#include "fem/column_deal.h"
#include "fem/condensed_contact.h"
#include "fem/contact_constraints.h"
#include "fem/contact_output.h"
#include "fem/contact_search_ahead.h"
#include "fem/contact_summary.h"
#include "fem/elastic_system.h"
#include "fem/load_control.h"
#include "fem/mortar_coupling.h"
#include "fem/rank_team.h"
#include "fem/run_state_bytes.h"
#include "fem/thread_chunks.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/grid_tools.h>

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>

namespace hipfai::fem {

void ensure_mpi_initialized() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) return;
  // Held until exit: finalizes PETSc and MPI after every solver object is gone. No thread limit
  // of its own (deal.II's default: the hardware threads, or DEAL_II_NUM_THREADS): the FE stages
  // share them among the ranks (threads_per_rank), limit_threads() lowers it.
  static int argc = 1;
  static char name[] = "hipfai";
  static char* args[] = {name, nullptr};
  static char** argv = args;
  static dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, dealii::numbers::invalid_unsigned_int);
}

const char* to_string(TeamColumns team_columns) {
  switch (team_columns) {
    case TeamColumns::kSpareCores: return "spare-cores";
    case TeamColumns::kEveryRank: return "every-rank";
  }
  return "?";
}

void limit_threads(unsigned int threads) {
  ensure_mpi_initialized();
  dealii::MultithreadInfo::set_thread_limit(threads == 0 ? dealii::numbers::invalid_unsigned_int : threads);
}

// The mesh's communicator. A substructured problem on several ranks is a team (fem/rank_team.h):
// its rank 0 solves the run alone, on a mesh of its own, and a helper sets up a mesh of its own
// only in a run where it is given columns (help_rank_0), so a helper that is given none does no
// work at all; both number the dofs as one rank does, so a block's columns are the same on
// either. The other solvers distribute the system over the ranks.
MPI_Comm system_communicator(MPI_Comm communicator, LinearSolver solver) {
  return solver == LinearSolver::kSubstructured ? MPI_COMM_SELF : communicator;
}

class ContactProblem::Impl {
 public:
  Impl(MPI_Comm communicator_in, ContactOptions options_in)
      : options(std::move(options_in)),
        built_substructured(options.linear_solver == LinearSolver::kSubstructured),
        communicator(communicator_in),
        system(system_communicator(communicator_in, options.linear_solver), options.fe_degree,
               options.mapping_degree),
        pcout(std::cout,
              options.verbose && dealii::Utilities::MPI::this_mpi_process(communicator) == 0),
        timer(pcout, dealii::TimerOutput::never, dealii::TimerOutput::wall_times),
        team(communicator),
        compliance(communicator) {}

  ContactResult run();
  void output_results(const std::string& file) const;

  ContactOptions options;
  bool built_substructured;  // the solver's kind at construction: the mesh is set up for it
  MPI_Comm communicator;  // the ranks of the problem (ContactProblem::communicator)
  ContactModel model;
  ElasticSystem system;

 private:
  friend class ContactProblem;  // displacement_at reads the solved state
  // The substructured path on several ranks (fem/rank_team.h): rank 0 solves, the others help
  // it with the compliance columns.
  bool team_run() const { return substructured() && team.has_helpers(); }
  void share_threads();
  void setup_system();
  // Rank 0's part of a run (all of it on one rank), after setup_system: the contact nodes, the
  // active sets and the results.
  ContactResult solve();
  // A helper's part of a team run: column solves until rank 0 sends the run's state.
  ContactResult help_rank_0();
  void find_contact_nodes();
  // The compliance columns of these nodes; on a team run rank 0 solves blocks of them until a
  // deal with its helpers pays (fem/column_deal.h), then tells them the missing nodes and the
  // deal, and the ranks solve the rest together.
  bool ensure_columns(const std::vector<int>& column_nodes);
  // Rank 0 of a team run: what each helper could take now (fem/column_deal.h).
  std::vector<ColumnDealHelper> deal_helpers();
  std::vector<Linearization> solve_active_set(
      const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets);
  // The active-set loop's shared steps: the starting set (and the log line naming the path),
  // and the next set from the solved forces and gaps (true: converged, the set is final).
  void start_active_sets(const std::vector<dealii::Tensor<1, 3>>& translations,
                         const ContactResult& result, const std::string& path);
  bool next_active_set(unsigned int iteration, bool load_controlled, ContactResult& result,
                       const std::string& detail);
  void solve_contact(std::vector<dealii::Tensor<1, 3>>& translations, ContactResult& result);
  void solve_contact_condensed(std::vector<dealii::Tensor<1, 3>>& translations,
                               ContactResult& result);
  bool substructured() const { return options.linear_solver == LinearSolver::kSubstructured; }
  void postprocess(ContactResult& result);

  dealii::ConditionalOStream pcout;
  dealii::TimerOutput timer;
  RankTeam team;
  ContactConstraints constraints;
  ActiveSetStrategy strategy;
  std::unique_ptr<ContactLinearSolver> solver;
  // The substructured path: the bodies' factors (kept across runs) and the condensed problem.
  BodyCompliance compliance;
  CondensedContact condensed;
  bool compliance_failed = false;
  unsigned int factorisations_before_run = 0;
  // Team runs, rank 0: whether this run factorises every body (a helper may then factorise),
  // how long the last factorisation took and one block's solve (measured; 0: none yet), and per
  // helper whether it holds the factors of rank 0's bodies in rank 0's frames.
  bool helpers_may_factorise = false;
  double factorisation_seconds = 0.0;
  double block_seconds = 0.0;
  std::vector<bool> helper_factorised;
  LinearSolver solver_kind = LinearSolver::kCgAmg;
  // The contact surfaces' faces, made once and turned with their bodies on later runs.
  ContactSurfaces surfaces;
  // The models of the runs the caller expects next, and the searches of their contact, run
  // beside the runs' solves.
  std::vector<ContactModel> upcoming;
  ContactSearchAhead search_ahead;
  bool searched_ahead = false;  // this run's nodes came from it
  // The searches ahead take a thread of their own: only when the caller expects more runs and
  // this one may use two threads.
  bool searches_ahead() const {
    return !upcoming.empty() && system.threads() >= 2;
  }
  std::vector<SlaveNode> nodes;
  std::vector<bool> active;
  // Of the last run: its solved state, the nodes' forces and gaps (empty: no state solved),
  // and the fields write_vtu shows.
  Linearization state;
  std::vector<double> force, gap;
  ContactFields fields;
  dealii::Vector<float> cell_von_mises;
};

void ContactProblem::Impl::share_threads() {
  // A team run's rank 0 does all but the column solves, so it takes the threads a one-rank run
  // has (with the searches ahead), but no more than the CPUs the launcher bound it to (Open MPI
  // binds each of 2 ranks to one core unless started with --bind-to none); the helpers solve
  // their columns on one thread (MUMPS runs serially here) and sleep otherwise. Other runs share
  // the threads among the ranks.
  if (!team_run()) {
    system.set_threads(0);
    return;
  }
  if (!team.leads()) {
    system.set_threads(1);
    return;
  }
  std::size_t threads = threads_per_rank(MPI_COMM_SELF);
  cpu_set_t cpus;
  if (sched_getaffinity(0, sizeof(cpus), &cpus) == 0)
    threads = std::min<std::size_t>(threads, std::max(1, CPU_COUNT(&cpus)));
  system.set_threads(threads);
}

void ContactProblem::Impl::setup_system() {
  dealii::TimerOutput::Scope scope(timer, "setup");
  system.place_bodies(model);
  system.setup(model);
  constraints.collect_fixed_dofs(system, model);
  surfaces.update(system, model);
  if (substructured()) {
    // The cell matrices are needed only to factorise a body anew.
    compliance.begin_run(system, constraints, model);
    compliance_failed = false;
    factorisations_before_run = compliance.factorisations();
    if (compliance.needs_factorisation()) {
      // This run's own contact search goes ahead of the factorisation, beside it.
      if (searches_ahead()) {
        std::vector<ContactModel> runs{model};
        runs.insert(runs.end(), upcoming.begin(), upcoming.end());
        search_ahead.plan(system, surfaces, runs, constraints.fixed_dofs(),
                          options.tangent_plane_cull);
      }
      // The factorisation is of the whole bodies (the substructured path is replicated, not
      // distributed, on several ranks), so it needs every cell's matrix. A helper factorises
      // only when it is first given columns, in a run where rank 0 factorises every body (so
      // that all its factors are in rank 0's frames; help_rank_0).
      helpers_may_factorise = compliance.needs_every_factorisation();
      if (!team_run() || team.leads()) {
        system.compute_cell_matrices(true);
        const dealii::Timer clock;
        compliance_failed = !compliance.factorise(system, constraints, model, timer, pcout);
        factorisation_seconds = clock.wall_time();
      }
      if (team_run() && team.leads())
        helper_factorised.assign(static_cast<std::size_t>(team.size() - 1), false);
    } else {
      helpers_may_factorise = false;
    }
    return;
  }
  system.compute_cell_matrices();
  if (!solver || solver_kind != options.linear_solver) {
    solver = make_contact_linear_solver(options.linear_solver, system, constraints, timer, pcout);
    solver_kind = options.linear_solver;
  }
  solver->begin_run(
      {options.linear_relative_tolerance, options.max_linear_iterations, options.low_rank_updates});
}

void ContactProblem::Impl::find_contact_nodes() {
  std::optional<std::vector<SlaveNode>> found;
  {
    // Waits only for a search of this run still in progress.
    dealii::TimerOutput::Scope scope(timer, "contact search ahead (waiting)");
    found = search_ahead.take(system, surfaces, model, constraints.fixed_dofs(),
                              options.tangent_plane_cull);
  }
  dealii::TimerOutput::Scope scope(timer, "contact search");
  searched_ahead = found.has_value();
  if (searched_ahead) pcout << "fem: contact nodes from the search run beside the previous run" << std::endl;
  nodes = found ? std::move(*found)
                : collect_slave_nodes(system, model, surfaces, constraints.fixed_dofs(),
                                      options.tangent_plane_cull);
  if (searches_ahead())
    search_ahead.plan(system, surfaces, upcoming, constraints.fixed_dofs(), options.tangent_plane_cull);
  upcoming.clear();
}

std::vector<Linearization> ContactProblem::Impl::solve_active_set(
    const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets) {
  // One active set, several rigid translations: only the inhomogeneities differ, so the solver
  // sets its matrix up once for all of them.
  std::vector<dealii::AffineConstraints<double>> constraint_sets;
  {
    dealii::TimerOutput::Scope scope(timer, "constraints");
    for (const auto& translations : translation_sets)
      constraint_sets.push_back(constraints.make(translations, nodes, active));
  }
  std::vector<dealii::Vector<double>> displacements =
      solver->solve({constraint_sets, translation_sets, nodes, active});
  dealii::TimerOutput::Scope scope(timer, "internal forces");
  std::vector<Linearization> states(displacements.size());
  for (std::size_t k = 0; k < states.size(); ++k)
    states[k].displacement = std::move(displacements[k]);
  system.add_internal_forces(states);
  return states;
}

void ContactProblem::Impl::start_active_sets(const std::vector<dealii::Tensor<1, 3>>& translations,
                                             const ContactResult& result, const std::string& path) {
  // Gaps well below the solver's resolution of the displacement count as closed.
  const double gap_tolerance = 1e-10 * system.diameter();
  strategy.begin_run({options.holder_switch_mm, options.warm_start_active_set}, gap_tolerance);
  active = strategy.initial(nodes, translations, system.dof_handler().n_dofs());
  pcout << "fem: " << result.statistics.n_cells << " cells, " << result.statistics.n_dofs
        << " dofs, " << nodes.size() << " contact nodes, " << result.statistics.n_ranks
        << " rank(s), " << path << std::endl;
}

bool ContactProblem::Impl::next_active_set(unsigned int iteration, bool load_controlled,
                                           ContactResult& result, const std::string& detail) {
  std::vector<bool> next = strategy.next(iteration, load_controlled, nodes, active, force, gap, pcout);
  std::size_t n_active = 0, changes = 0;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    n_active += next[n];
    changes += next[n] != active[n];
  }
  pcout << "fem: active-set iteration " << iteration << ": " << n_active << " active, " << changes
        << " changed" << detail << std::endl;
  if (changes == 0) {
    result.status = ContactStatus::kConverged;
    return true;
  }
  active = std::move(next);
  return false;
}

void ContactProblem::Impl::solve_contact(std::vector<dealii::Tensor<1, 3>>& translations,
                                         ContactResult& result) {
  const LoadControl load_control(model);
  start_active_sets(translations, result, to_string(options.linear_solver));
  result.status = ContactStatus::kActiveSetNotConverged;
  for (unsigned int iteration = 1; iteration <= options.max_active_set_iterations; ++iteration) {
    result.statistics.active_set_iterations = iteration;
    const unsigned int iterations_before = solver->statistics().linear_iterations;
    if (load_control.empty()) {
      state = std::move(solve_active_set({translations}).front());
    } else {
      std::vector<Linearization> probes =
          solve_active_set(load_control.probe_translations(translations));
      if (!load_control.balance(model, constraints.bonded_dofs(), nodes, active, probes,
                                translations, state)) {
        result.status = ContactStatus::kNoContact;
        break;
      }
    }
    if (solver->statistics().failed) {
      result.status = ContactStatus::kLinearSolverFailed;
      break;
    }
    evaluate_nodes(nodes, state, translations, force, gap);
    const std::string detail =
        ", " + std::to_string(solver->statistics().linear_iterations - iterations_before) +
        " CG iterations";
    if (next_active_set(iteration, !load_control.empty(), result, detail)) break;
  }
}

void ContactProblem::Impl::solve_contact_condensed(std::vector<dealii::Tensor<1, 3>>& translations,
                                                   ContactResult& result) {
  // The same active-set rules as solve_contact; each set is solved on the condensed interface
  // (fem/condensed_contact.h) and the whole displacement recovered once, after the last set.
  const unsigned int columns_before = compliance.solved_columns();
  const bool load_controlled = !LoadControl(model).empty();
  start_active_sets(translations, result, to_string(options.linear_solver));
  {
    dealii::TimerOutput::Scope scope(timer, "condensation");
    condensed.begin_run(compliance, model, nodes, translations,
                        system.threads());
  }
  result.status = compliance_failed ? ContactStatus::kLinearSolverFailed
                                    : ContactStatus::kActiveSetNotConverged;
  bool solved = false;
  for (unsigned int iteration = 1;
       !compliance_failed && iteration <= options.max_active_set_iterations; ++iteration) {
    result.statistics.active_set_iterations = iteration;
    CondensedOutcome outcome = CondensedOutcome::kFailed;
    bool columns = false;
    {
      dealii::TimerOutput::Scope scope(timer, "compliance columns");
      columns = ensure_columns(condensed.column_nodes(active));
    }
    if (columns) {
      dealii::TimerOutput::Scope scope(timer, "active set (condensed)");
      outcome = condensed.solve(active, translations, force, gap, pcout);
    }
    if (outcome == CondensedOutcome::kNoContact) {
      result.status = ContactStatus::kNoContact;
      break;
    }
    if (outcome == CondensedOutcome::kFailed) {
      result.status = ContactStatus::kLinearSolverFailed;
      break;
    }
    solved = true;
    if (next_active_set(iteration, load_controlled, result, "")) break;
  }
  {
    dealii::TimerOutput::Scope scope(timer, "recovery");
    state = Linearization();
    state.displacement.reinit(system.dof_handler().n_dofs());
    std::vector<dealii::Tensor<1, 3>> no_force;
    if (!solved) no_force.assign(compliance.n_nodes(), dealii::Tensor<1, 3>());
    if (!compliance_failed &&
        !compliance.recover(translations, solved ? condensed.node_forces() : no_force,
                            state.displacement, pcout))
      result.status = ContactStatus::kLinearSolverFailed;
    if (!solved) {
      force.assign(nodes.size(), 0.0);
      gap.assign(nodes.size(), 0.0);
    }
  }
  result.statistics.factorisations = compliance.factorisations() - factorisations_before_run;
  result.statistics.linear_solves = compliance.solved_columns() - columns_before + 1;
}

bool ContactProblem::Impl::ensure_columns(const std::vector<int>& column_nodes) {
  if (!team_run()) return compliance.ensure_columns(column_nodes, pcout);
  const std::vector<int> missing = compliance.missing_columns(column_nodes);
  if (missing.empty()) return true;  // the helpers sleep on
  const BodyCompliance::ColumnBlocks blocks = compliance.column_blocks(missing);
  const std::size_t n = blocks.blocks.size();
  // Rank 0 solves blocks alone until the rest is worth dealing (each block timed for the deal).
  std::size_t first = 0;
  ColumnDeal deal;
  for (; first < n; ++first) {
    if (options.team_columns == TeamColumns::kEveryRank) {
      deal = deal_columns_evenly(n - first, deal_helpers());
      break;
    }
    if (block_seconds > 0.0) {
      deal = deal_columns({n - first, block_seconds, factorisation_seconds, deal_helpers()});
      if (deal.dealt()) break;
    }
    const dealii::Timer clock;
    if (!compliance.solve_column_block(blocks, first, pcout)) return false;
    block_seconds = clock.wall_time();
  }
  if (first == n) return true;
  std::vector<char> factorise(deal.factorise.begin(), deal.factorise.end());
  ByteWriter message;
  message.io(missing);
  message.io(first);
  message.io(deal.counts);
  message.io(factorise);
  team.send(RankTeam::Message::kColumns, message.bytes());
  pcout << "fem: column blocks " << first + 1 << "-" << n << " dealt to the ranks:";
  for (const std::size_t count : deal.counts) pcout << " " << count;
  pcout << std::endl;
  if (!compliance.share_column_blocks(blocks, first, deal.counts, true, pcout)) return false;
  for (std::size_t h = 0; h < helper_factorised.size(); ++h) {
    if (deal.factorise[h + 1]) helper_factorised[h] = true;
  }
  return true;
}

std::vector<ColumnDealHelper> ContactProblem::Impl::deal_helpers() {
  const std::vector<RankTeam::HelperCore> cores = team.helper_cores(search_ahead.remaining_seconds());
  std::vector<ColumnDealHelper> helpers(helper_factorised.size());
  for (std::size_t h = 0; h < helpers.size(); ++h) {
    helpers[h].has_core = cores[h].has_core;
    helpers[h].busy_seconds = cores[h].busy_seconds;
    helpers[h].factorised = helper_factorised[h];
    helpers[h].may_factorise = helpers_may_factorise;
  }
  return helpers;
}

void ContactProblem::Impl::postprocess(ContactResult& result) {
  {
    dealii::TimerOutput::Scope scope(timer, "results");
    summarize_contact(nodes, active, force, gap, model.contact_pairs.size(),
                      options.peak_average_radius_mm, result);
  }
  {
    dealii::TimerOutput::Scope scope(timer, "stresses");
    VonMisesField field = system.von_mises(state.displacement, model);
    summarize_stress(field, options.peak_average_radius_mm, result,
                     system.threads());
    cell_von_mises = std::move(field.cell_max);
  }
  // Every rank holds the same replicated numbers, so all ranks reach the same verdict.
  if (!make_finite(result, state.displacement)) result.status = ContactStatus::kNonFinite;
  fields.pressure_mpa.assign(nodes.size(), 0.0);
  fields.gap_mm.assign(nodes.size(), 0.0);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    fields.pressure_mpa[n] = result.nodes[n].pressure_mpa;
    fields.gap_mm[n] = result.nodes[n].gap_mm;
  }
  fields.active = active;
  for (float& value : cell_von_mises) {
    if (!std::isfinite(value)) value = 0.0f;
  }
  if (result.status == ContactStatus::kConverged)
    strategy.remember_converged(nodes, active, state.displacement);
}

ContactResult ContactProblem::Impl::run() {
  const dealii::Timer wall_clock;
  timer.reset();
  if (substructured() != built_substructured) {
    throw_error("fem: the substructured solver is chosen at construction (its mesh is set up for it), "
                "not between runs");
  }
  check_references(model);
  share_threads();
  const unsigned int columns_before = compliance.columns_solved_here();
  ContactResult result;
  if (team_run() && !team.leads()) {
    result = help_rank_0();  // sets up its mesh only when given columns
  } else if (team_run()) {
    // The helpers wait for rank 0's messages until the run's result: an error here must reach
    // them too, or they would wait for ever.
    try {
      setup_system();
      result = solve();
    } catch (const std::exception& error) {
      const std::string what = error.what();
      team.send(RankTeam::Message::kRunFailed, std::vector<char>(what.begin(), what.end()));
      throw;
    }
    dealii::TimerOutput::Scope scope(timer, "result to the other ranks");
    ByteWriter message;
    write_run_state({result}, message);
    team.send(RankTeam::Message::kRunDone, message.bytes());
  } else {
    setup_system();
    result = solve();
  }
  result.statistics.rank_columns = compliance.columns_solved_here() - columns_before;
  if (!options.vtu_file.empty()) {
    dealii::TimerOutput::Scope scope(timer, "output");
    output_results(options.vtu_file);
  }
  result.statistics.wall_time_s = wall_clock.wall_time();
  const SolveStatistics& counts = result.statistics;
  pcout << "fem: " << to_string(result.status) << " after " << counts.active_set_iterations
        << " active-set iterations, " << counts.linear_solves << " linear solves, "
        << counts.linear_iterations << " CG iterations, " << counts.factorisations
        << " factorisations, " << counts.low_rank_updates << " low-rank updates, "
        << counts.wall_time_s << " s\n";
  timer.print_summary();
  return result;
}

ContactResult ContactProblem::Impl::solve() {
  find_contact_nodes();

  ContactResult result;
  result.statistics.n_cells = system.triangulation().n_global_active_cells();
  result.statistics.n_dofs = system.dof_handler().n_dofs();
  result.statistics.n_ranks = dealii::Utilities::MPI::n_mpi_processes(communicator);
  result.statistics.searched_ahead = searched_ahead;
  std::vector<dealii::Tensor<1, 3>> translations;
  for (const RigidBody& body : model.rigid_bodies) translations.push_back(body.translation_mm);
  state = Linearization();
  force.clear();
  gap.clear();

  if (substructured()) {
    solve_contact_condensed(translations, result);
  } else {
    solve_contact(translations, result);
    solver->end_run();  // the factor's memory goes now
    const LinearSolverStatistics& statistics = solver->statistics();
    result.statistics.factorisations = statistics.factorisations;
    result.statistics.low_rank_updates = statistics.low_rank_updates;
    result.statistics.linear_solves = statistics.linear_solves;
    result.statistics.linear_iterations = statistics.linear_iterations;
  }
  result.rigid_translation_mm = translations;
  postprocess(result);
  return result;
}

ContactResult ContactProblem::Impl::help_rank_0() {
  std::vector<char> payload;
  bool set_up = false;
  while (true) {
    switch (team.receive(payload)) {
      case RankTeam::Message::kColumns: {
        // This run's mesh, placement and bodies, as rank 0 set them up (the same model on every
        // rank), made the first time the run gives this rank columns.
        ByteReader message(payload);
        std::vector<int> missing;
        std::size_t first = 0;
        std::vector<std::size_t> counts;
        std::vector<char> factorise;
        message.io(missing);
        message.io(first);
        message.io(counts);
        message.io(factorise);
        bool ready = true;
        // An error here is this rank's failed share: the others wait for its verdict in the
        // collectives.
        try {
          if (!set_up) setup_system();
          set_up = true;
          if (factorise.at(static_cast<std::size_t>(team.rank()))) {
            // This run's placement is the frame rank 0 factorised every body in.
            system.compute_cell_matrices(true);
            ready = compliance.factorise(system, constraints, model, timer, pcout, true);
          }
        } catch (const std::exception&) {
          ready = false;
        }
        // A failed solve is every rank's verdict (share_column_blocks agrees on it); rank 0 acts
        // on it.
        compliance.share_column_blocks(compliance.column_blocks(missing), first, counts, ready, pcout);
        break;
      }
      case RankTeam::Message::kRunFailed:
        throw_error("fem: rank 0 failed: ", std::string(payload.begin(), payload.end()));
      case RankTeam::Message::kRunDone: {
        ByteReader message(payload);
        RunState run = read_run_state(message);
        // The fields stay on rank 0, which writes the VTU files alone (output_results).
        state = Linearization();
        cell_von_mises.reinit(0);
        nodes.clear();
        fields = ContactFields();
        return run.result;
      }
    }
  }
}

void ContactProblem::Impl::output_results(const std::string& file) const {
  if (team_run() && !team.leads()) return;  // rank 0's mesh has every cell and the fields
  write_contact_vtu(file, system, state.displacement, cell_von_mises, nodes, fields);
}

ContactProblem::ContactProblem(MPI_Comm communicator, ContactOptions options) {
  ensure_mpi_initialized();
  impl_ = std::make_unique<Impl>(communicator, std::move(options));
}

ContactProblem::~ContactProblem() = default;

dealii::parallel::shared::Triangulation<3>& ContactProblem::triangulation() {
  return impl_->system.triangulation();
}

ContactResult ContactProblem::run() {
  // Checked before the solve, not when the peaks are taken after it.
  const double radius_mm = impl_->options.peak_average_radius_mm;
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    throw_error("fem model: peak_average_radius_mm must be finite and > 0, got ", radius_mm);
  }
  return impl_->run();
}

dealii::Tensor<1, 3> ContactProblem::displacement_at(const dealii::Point<3>& point_mm) const {
  if (impl_->team_run() && !impl_->team.leads())
    throw_error("fem: on a substructured run over several ranks only rank 0 holds the displacement");
  return impl_->system.point_value(impl_->state.displacement, point_mm);
}

MPI_Comm ContactProblem::communicator() const { return impl_->communicator; }

ContactOptions& ContactProblem::options() { return impl_->options; }

ContactModel& ContactProblem::model() { return impl_->model; }

const ContactModel& ContactProblem::model() const { return impl_->model; }

void ContactProblem::write_vtu(const std::string& file) const { impl_->output_results(file); }

void ContactProblem::expect_next(std::vector<ContactModel> upcoming) {
  impl_->upcoming = std::move(upcoming);
}

}  // namespace hipfai::fem
