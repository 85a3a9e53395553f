#include "fem/body_compliance.h"

#include "core/disjoint_sets.h"
#include "core/error.h"
#include "fem/rank_team.h"

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

namespace hipfai::fem {

using dealii::types::global_dof_index;

namespace {

// Compliance columns are solved in blocks of this many nodes (3 right-hand sides each), MUMPS
// blocking them all at once: large enough for its block solve to read the factor once for many
// columns (144 instead of its default 32 made the columns 15 % faster at the default level),
// small enough that the dense block stays ~100 MB at the fine level.
constexpr std::size_t kNodesPerBlock = 48;

dealii::Tensor<2, 3> rotation_of(const ContactModel& model, int rigid_body) {
  if (rigid_body < 0) return dealii::unit_symmetric_tensor<3>();
  return model.rigid_bodies[rigid_body].rotation;
}

double max_abs_difference(const dealii::Tensor<2, 3>& a, const dealii::Tensor<2, 3>& b) {
  double d = 0.0;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j) d = std::max(d, std::abs(a[i][j] - b[i][j]));
  return d;
}

}  // namespace

BodyCompliance::~BodyCompliance() {
  for (Body& body : bodies_) release(body);
}

void BodyCompliance::release(Body& body) {
  body.cholesky.reset();
  if (body.matrix) MatDestroy(&body.matrix);
  body.matrix = nullptr;
  body.row_start.clear();
  body.columns.clear();
  body.values.clear();
  body.node_columns.clear();
  body.liftings.clear();
  body.extra.clear();
  body.stale = true;
}

void BodyCompliance::begin_run(const ElasticSystem& system, const ContactConstraints& constraints,
                               const ContactModel& model) {
  if (constraints.has_hanging_nodes()) {
    throw_error("fem: the substructured solver does not support hanging nodes (use --solver direct)");
  }
  const dealii::DoFHandler<3>& dof_handler = system.dof_handler();
  const global_dof_index n_dofs = dof_handler.n_dofs();
  const std::size_t key = system.dof_layout_key();
  if (key != layout_key_ || bodies_.size() != model.bodies.size()) {
    for (Body& body : bodies_) release(body);
    bodies_.clear();
    bodies_.resize(model.bodies.size());
    layout_key_ = key;
    std::map<dealii::types::material_id, int> body_of_material;
    for (std::size_t b = 0; b < model.bodies.size(); ++b)
      body_of_material[model.bodies[b].material_id] = static_cast<int>(b);
    node_of_dof_.assign(n_dofs, -1);
    node_dofs_.clear();
    body_of_node_.clear();
    std::vector<global_dof_index> dofs(system.fe().n_dofs_per_cell());
    const unsigned int n_base = system.fe().base_element(0).n_dofs_per_cell();
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      const auto it = body_of_material.find(cell->material_id());
      if (it == body_of_material.end()) {
        throw_error("fem model: cell with material id ", static_cast<int>(cell->material_id()),
                    " belongs to no body");
      }
      for (unsigned int i = 0; i < n_base; ++i) {
        NodeDofs node;
        for (unsigned int c = 0; c < 3; ++c) node[c] = dofs[system.system_index(i, c)];
        int& index = node_of_dof_[node[0]];
        if (index < 0) {
          index = static_cast<int>(node_dofs_.size());
          node_dofs_.push_back(node);
          body_of_node_.push_back(it->second);
          for (unsigned int c = 1; c < 3; ++c) node_of_dof_[node[c]] = index;
        } else if (body_of_node_[index] != it->second) {
          throw_error("fem: the substructured solver needs separate bodies; bodies '",
                      model.bodies[body_of_node_[index]].name, "' and '",
                      model.bodies[it->second].name, "' share a node (use --solver direct)");
        }
      }
    }
    body_index_of_dof_.assign(n_dofs, -1);
    for (std::size_t p = 0; p < node_dofs_.size(); ++p) {
      Body& body = bodies_[body_of_node_[p]];
      body.nodes.push_back(static_cast<int>(p));
      for (unsigned int c = 0; c < 3; ++c) {
        body_index_of_dof_[node_dofs_[p][c]] = static_cast<int>(body.dofs.size());
        body.dofs.push_back(node_dofs_[p][c]);
      }
    }
    // The connected pieces (a labrum open at the notch is a body in two): nodes joined through
    // their cells, each piece named by one of its nodes.
    DisjointSets pieces(node_dofs_.size());
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      const auto first = static_cast<std::size_t>(node_of_dof_[dofs[system.system_index(0, 0)]]);
      for (unsigned int i = 1; i < n_base; ++i)
        pieces.unite(static_cast<std::size_t>(node_of_dof_[dofs[system.system_index(i, 0)]]), first);
    }
    piece_of_node_.resize(node_dofs_.size());
    for (std::size_t p = 0; p < piece_of_node_.size(); ++p) piece_of_node_[p] = static_cast<int>(pieces.find(p));

    // Contact-surface nodes: on a slave or deformable master boundary of a contact pair.
    std::set<dealii::types::boundary_id> contact_ids;
    for (const ContactPair& pair : model.contact_pairs) {
      contact_ids.insert(pair.slave_boundary_id);
      if (pair.master_rigid_body < 0) contact_ids.insert(pair.master_boundary_id);
    }
    surface_index_.assign(node_dofs_.size(), -1);
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      for (const unsigned int face_no : cell->face_indices()) {
        const auto face = cell->face(face_no);
        if (!face->at_boundary() || !contact_ids.count(face->boundary_id())) continue;
        for (unsigned int i = 0; i < dofs.size(); ++i) {
          if (!system.support_on_face(face_no, i) || system.component_of(i) != 0) continue;
          const int node = node_of_dof_[dofs[i]];
          if (surface_index_[node] >= 0) continue;
          Body& body = bodies_[body_of_node_[node]];
          surface_index_[node] = static_cast<int>(body.surface_nodes.size());
          body.surface_nodes.push_back(node);
        }
      }
    }
  }

  // Each body must be held by its bonded boundary, and so each connected piece of it: the
  // factorisation is of the body alone, so a body or a piece of one that only the contact holds
  // (a rigid motion left free) has a singular stiffness.
  std::vector<bool> is_bonded(n_dofs, false);
  for (const BondedDof& dof : constraints.bonded_dofs()) is_bonded[dof.dof] = true;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    struct Piece {
      std::size_t nodes = 0;
      std::vector<dealii::Point<3>> held;  // its bonded nodes
    };
    std::map<int, Piece> pieces;
    for (const int node : bodies_[b].nodes) {
      Piece& piece = pieces[piece_of_node_[node]];
      ++piece.nodes;
      const NodeDofs& dofs = node_dofs_[node];
      if (is_bonded[dofs[0]] && is_bonded[dofs[1]] && is_bonded[dofs[2]])
        piece.held.push_back(system.support_points()[dofs[0]]);
    }
    for (const auto& [id, piece] : pieces) {
      const std::vector<dealii::Point<3>>& points = piece.held;
      bool spans_a_plane = false;
      for (std::size_t i = 2; i < points.size() && !spans_a_plane; ++i) {
        const double area = dealii::cross_product_3d(points[1] - points[0], points[i] - points[0]).norm();
        spans_a_plane = area > 1e-12 * std::max(1.0, points[1].distance(points[0]) * points[i].distance(points[0]));
      }
      if (spans_a_plane) continue;
      if (pieces.size() == 1) {
        throw_error("fem: the substructured solver needs every deformable body bonded to a bone; '",
                    model.bodies[b].name, "' is held only by its contacts (use --solver direct)");
      }
      throw_error("fem: the substructured solver needs every deformable body bonded to a bone; a piece of '",
                  model.bodies[b].name, "' (", piece.nodes, " of its ", bodies_[b].nodes.size(), " nodes, one of ",
                  pieces.size(), " pieces) is held only by its contacts (use --solver direct)");
    }
  }

  // Is each body still the one that was factorised, up to its rigid rotation?
  const std::vector<bool>& fixed = constraints.fixed_dofs();
  std::vector<double> extra_now(n_dofs, 0.0);
  for (const BondedDof& bonded : constraints.bonded_dofs()) extra_now[bonded.dof] = bonded.extra;
  const double scale = std::max(1.0, system.diameter());
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    Body& body = bodies_[b];
    body.rigid_body = model.bodies[b].bonded_rigid_body;
    const dealii::Tensor<2, 3> now = rotation_of(model, body.rigid_body);
    if (!body.cholesky) {
      body.stale = true;
      body.rotation = dealii::unit_symmetric_tensor<3>();
      continue;
    }
    const dealii::Tensor<2, 3> relative = now * dealii::transpose(body.factor_rotation);
    bool same = body.factor_lame == std::pair<double, double>{
                                        model.bodies[b].material.lame_lambda_mpa(),
                                        model.bodies[b].material.shear_modulus_mpa()};
    if (body.partly_fixed_nodes &&
        max_abs_difference(relative, dealii::unit_symmetric_tensor<3>()) > 1e-14)
      same = false;
    const dealii::Point<3> centre =
        body.rigid_body >= 0 ? model.rigid_bodies[body.rigid_body].rotation_center_mm
                             : dealii::Point<3>();
    for (std::size_t i = 0; same && i < body.dofs.size(); ++i) {
      const global_dof_index dof = body.dofs[i];
      if (fixed[dof] != body.factor_fixed[i]) same = false;
    }
    const std::vector<dealii::Point<3>>& points = system.support_points();
    for (std::size_t i = 0; same && i < body.dofs.size(); i += 3) {
      const dealii::Point<3> expected = centre + relative * (body.factor_points[i / 3] - centre);
      if (expected.distance(points[body.dofs[i]]) > 1e-10 * scale) same = false;
      dealii::Tensor<1, 3> extra;
      for (unsigned int c = 0; c < 3; ++c) extra[c] = extra_now[body.dofs[i + c]];
      const dealii::Tensor<1, 3> extra_body = dealii::transpose(relative) * extra;
      for (unsigned int c = 0; c < 3; ++c) {
        if (std::abs(extra_body[c] - body.factor_extra[i + c]) > 1e-12 * (1.0 + std::abs(extra_body[c])))
          same = false;
      }
    }
    body.stale = !same;
    body.rotation = same ? relative : dealii::unit_symmetric_tensor<3>();
  }
}

bool BodyCompliance::needs_factorisation() const {
  return std::any_of(bodies_.begin(), bodies_.end(), [](const Body& body) { return body.stale; });
}

bool BodyCompliance::needs_every_factorisation() const {
  return std::all_of(bodies_.begin(), bodies_.end(), [](const Body& body) { return body.stale; });
}

bool BodyCompliance::factorise(const ElasticSystem& system, const ContactConstraints& constraints,
                               const ContactModel& model, dealii::TimerOutput& timer,
                               dealii::ConditionalOStream& log, bool every_body) {
  dealii::TimerOutput::Scope scope(timer, "factorisation");
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    if (!bodies_[b].stale && !every_body) continue;
    if (!factorise_body(b, system, constraints, model, log)) return false;
  }
  return true;
}

bool BodyCompliance::factorise_body(std::size_t b, const ElasticSystem& system,
                                    const ContactConstraints& constraints,
                                    const ContactModel& model, dealii::ConditionalOStream& log) {
  Body& body = bodies_[b];
  release(body);
  number_free_dofs(body, constraints.fixed_dofs());
  const std::size_t n = body.dofs.size();
  body.factor_points.resize(n / 3);
  for (std::size_t i = 0; i < n; i += 3)
    body.factor_points[i / 3] = system.support_points()[body.dofs[i]];
  body.factor_rotation = rotation_of(model, body.rigid_body);
  body.rotation = dealii::unit_symmetric_tensor<3>();
  body.factor_lame = {model.bodies[b].material.lame_lambda_mpa(),
                      model.bodies[b].material.shear_modulus_mpa()};

  const BondedData bonded = bonded_data(b, body, constraints);
  const std::size_t n_lift = bonded.data.size();
  std::vector<double> rhs(n_lift * static_cast<std::size_t>(body.n_free), 0.0);
  const std::vector<dealii::DoFHandler<3>::active_cell_iterator> cells =
      factorise_free_stiffness(b, body, system, bonded, rhs);

  // The liftings at the free dofs, then their reactions at the bonded dofs.
  if (n_lift > 0 && !solve_block(body, rhs, n_lift, log)) return false;
  body.liftings.assign(3 * body.lifted_bodies.size(), {});
  for (std::size_t l = 0; l < n_lift; ++l) {
    std::vector<double> lifting = bonded.data[l];
    for (std::size_t i = 0; i < n; ++i) {
      if (body.free_index[i] >= 0) lifting[i] = rhs[l * body.n_free + body.free_index[i]];
    }
    if (l < 3 * body.lifted_bodies.size())
      body.liftings[l] = std::move(lifting);
    else
      body.extra = std::move(lifting);
  }
  add_lifting_reactions(body, system, cells, bonded);
  body.node_columns.assign(body.surface_nodes.size(), {});
  body.stale = false;
  return true;
}

void BodyCompliance::number_free_dofs(Body& body, const std::vector<bool>& fixed) {
  const std::size_t n = body.dofs.size();
  body.factor_fixed.assign(n, false);
  body.free_index.assign(n, -1);
  body.n_free = 0;
  body.partly_fixed_nodes = false;
  for (std::size_t i = 0; i < n; i += 3) {
    unsigned int fixed_components = 0;
    for (unsigned int c = 0; c < 3; ++c) {
      body.factor_fixed[i + c] = fixed[body.dofs[i + c]];
      fixed_components += body.factor_fixed[i + c];
      if (!body.factor_fixed[i + c]) body.free_index[i + c] = body.n_free++;
    }
    if (fixed_components == 1 || fixed_components == 2) body.partly_fixed_nodes = true;
  }
}

BodyCompliance::BondedData BodyCompliance::bonded_data(std::size_t b, Body& body,
                                                       const ContactConstraints& constraints) {
  // Liftings: data on the bonded dofs; 3 per rigid body the body is bonded to, then the extra.
  // The body's bonded dofs once: index into its dofs, its rigid body's place in lifted_bodies
  // (-1: bonded to none), component and extra displacement.
  BondedData out;
  const std::size_t n = body.dofs.size();
  body.lifted_bodies.clear();
  body.factor_extra.assign(n, 0.0);
  for (const BondedDof& bonded : constraints.bonded_dofs()) {
    if (body_of_node_[node_of_dof_[bonded.dof]] != static_cast<int>(b)) continue;
    int k = -1;
    if (bonded.rigid_body >= 0) {
      const auto it =
          std::find(body.lifted_bodies.begin(), body.lifted_bodies.end(), bonded.rigid_body);
      k = static_cast<int>(it - body.lifted_bodies.begin());
      if (it == body.lifted_bodies.end()) body.lifted_bodies.push_back(bonded.rigid_body);
    }
    const int i = body_index_of_dof_[bonded.dof];
    out.held.push_back({i, k, bonded.component, bonded.extra});
    body.factor_extra[i] = bonded.extra;
    out.has_extra = out.has_extra || bonded.extra != 0.0;
  }
  const std::size_t n_lift = 3 * body.lifted_bodies.size() + (out.has_extra ? 1 : 0);
  out.data.assign(n_lift, std::vector<double>(n, 0.0));
  for (const Held& h : out.held) {
    if (h.k >= 0) out.data[3 * h.k + h.component][h.i] = 1.0;
    if (out.has_extra) out.data.back()[h.i] = h.extra;
  }
  return out;
}

std::vector<dealii::DoFHandler<3>::active_cell_iterator> BodyCompliance::factorise_free_stiffness(
    std::size_t b, Body& body, const ElasticSystem& system, const BondedData& bonded,
    std::vector<double>& rhs) {
  // K restricted to the free dofs (upper triangle), and -K_fd d for each lifting.
  const std::size_t n_lift = bonded.data.size();
  dealii::DynamicSparsityPattern dsp(body.n_free);
  const unsigned int dofs_per_cell = system.fe().n_dofs_per_cell();
  std::vector<global_dof_index> dofs(dofs_per_cell);
  std::vector<int> local(dofs_per_cell);
  std::vector<dealii::DoFHandler<3>::active_cell_iterator> cells;
  for (const auto& cell : system.dof_handler().active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    if (body_of_node_[node_of_dof_[dofs[0]]] != static_cast<int>(b)) continue;
    cells.push_back(cell);
    for (unsigned int i = 0; i < dofs_per_cell; ++i) {
      const PetscInt r = body.free_index[body_index_of_dof_[dofs[i]]];
      if (r < 0) continue;
      for (unsigned int j = 0; j < dofs_per_cell; ++j) {
        const PetscInt c = body.free_index[body_index_of_dof_[dofs[j]]];
        if (c >= r) dsp.add(r, c);
      }
    }
  }
  dealii::SparsityPattern pattern;
  pattern.copy_from(dsp);
  dealii::SparseMatrix<double> k(pattern);
  for (const auto& cell : cells) {
    cell->get_dof_indices(dofs);
    const dealii::FullMatrix<double>& matrix = system.cell_matrix(cell->active_cell_index());
    for (unsigned int i = 0; i < dofs_per_cell; ++i) local[i] = body_index_of_dof_[dofs[i]];
    for (unsigned int i = 0; i < dofs_per_cell; ++i) {
      const PetscInt r = body.free_index[local[i]];
      if (r < 0) continue;
      for (unsigned int j = 0; j < dofs_per_cell; ++j) {
        const PetscInt c = body.free_index[local[j]];
        if (c >= r) {
          k.add(r, c, matrix(i, j));
        } else if (c < 0) {
          for (std::size_t l = 0; l < n_lift; ++l)
            rhs[l * body.n_free + r] -= matrix(i, j) * bonded.data[l][local[j]];
        }
      }
    }
  }
  // SBAIJ wants each row's columns ascending; deal.II stores the diagonal first, which in the
  // upper triangle is the smallest column anyway.
  body.row_start.assign(body.n_free + 1, 0);
  body.columns.reserve(k.n_nonzero_elements());
  body.values.reserve(k.n_nonzero_elements());
  for (PetscInt r = 0; r < body.n_free; ++r) {
    std::vector<std::pair<PetscInt, double>> row;
    for (auto entry = k.begin(r); entry != k.end(r); ++entry)
      row.emplace_back(static_cast<PetscInt>(entry->column()), entry->value());
    std::sort(row.begin(), row.end());
    for (const auto& [column, value] : row) {
      body.columns.push_back(column);
      body.values.push_back(value);
    }
    body.row_start[r + 1] = static_cast<PetscInt>(body.columns.size());
  }
  k.clear();
  MatCreateSeqSBAIJWithArrays(PETSC_COMM_SELF, 1, body.n_free, body.n_free, body.row_start.data(),
                              body.columns.data(), body.values.data(), &body.matrix);
  MatSetOption(body.matrix, MAT_SPD, PETSC_TRUE);
  body.cholesky = std::make_unique<CholeskySolve>(PETSC_COMM_SELF, body.matrix);
  body.cholesky->factorise();
  body.cholesky->set_right_hand_side_blocking(static_cast<PetscInt>(3 * kNodesPerBlock));
  ++factorisations_;
  return cells;
}

void BodyCompliance::add_lifting_reactions(
    Body& body, const ElasticSystem& system,
    const std::vector<dealii::DoFHandler<3>::active_cell_iterator>& cells, const BondedData& bonded) {
  const std::size_t n_lift = bonded.data.size();
  const unsigned int dofs_per_cell = system.fe().n_dofs_per_cell();
  std::vector<global_dof_index> dofs(dofs_per_cell);
  std::vector<int> local(dofs_per_cell);
  std::vector<std::vector<double>> reaction(n_lift, std::vector<double>(body.dofs.size(), 0.0));
  for (const auto& cell : cells) {
    cell->get_dof_indices(dofs);
    const dealii::FullMatrix<double>& matrix = system.cell_matrix(cell->active_cell_index());
    for (unsigned int i = 0; i < dofs_per_cell; ++i) local[i] = body_index_of_dof_[dofs[i]];
    for (std::size_t l = 0; l < n_lift; ++l) {
      const std::vector<double>& u = l < body.liftings.size() ? body.liftings[l] : body.extra;
      for (unsigned int i = 0; i < dofs_per_cell; ++i) {
        if (body.free_index[local[i]] >= 0) continue;
        double sum = 0.0;
        for (unsigned int j = 0; j < dofs_per_cell; ++j) sum += matrix(i, j) * u[local[j]];
        reaction[l][local[i]] += sum;
      }
    }
  }
  const std::size_t m = body.lifted_bodies.size();
  body.a.assign(m, std::vector<dealii::Tensor<2, 3>>(m));
  body.r0.assign(m, dealii::Tensor<1, 3>());
  for (const Held& h : bonded.held) {
    if (h.k < 0) continue;
    for (std::size_t col = 0; col < m; ++col) {
      for (unsigned int c = 0; c < 3; ++c)
        body.a[h.k][col][h.component][c] += reaction[3 * col + c][h.i];
    }
    if (bonded.has_extra) body.r0[h.k][h.component] += reaction.back()[h.i];
  }
}

bool BodyCompliance::solve_block(Body& body, std::vector<double>& rhs, std::size_t k,
                                 dealii::ConditionalOStream& log) {
  std::vector<double> x(rhs.size());
  if (!body.cholesky->solve_block(body.n_free, static_cast<PetscInt>(k), rhs.data(), x.data(), log))
    return false;
  rhs.swap(x);
  return true;
}

bool BodyCompliance::ensure_columns(const std::vector<int>& nodes, dealii::ConditionalOStream& log) {
  const ColumnBlocks blocks = column_blocks(missing_columns(nodes));
  for (std::size_t g = 0; g < blocks.blocks.size(); ++g) {
    if (!solve_column_block(blocks, g, log)) return false;
  }
  return true;
}

std::vector<int> BodyCompliance::missing_columns(const std::vector<int>& nodes) const {
  std::vector<int> missing;
  for (const int node : nodes) {
    if (surface_index_[node] < 0)
      throw_error("fem: a contact constraint names a node off every contact surface");
    if (!columns(node)) missing.push_back(node);
  }
  std::sort(missing.begin(), missing.end());
  missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
  return missing;
}

BodyCompliance::ColumnBlocks BodyCompliance::column_blocks(const std::vector<int>& missing) const {
  ColumnBlocks out;
  out.nodes.resize(bodies_.size());
  for (const int node : missing) out.nodes[body_of_node_[node]].push_back(node);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    for (std::size_t first = 0; first < out.nodes[b].size(); first += kNodesPerBlock)
      out.blocks.push_back({b, first, std::min(kNodesPerBlock, out.nodes[b].size() - first)});
  }
  return out;
}

bool BodyCompliance::share_column_blocks(const ColumnBlocks& blocks, std::size_t first,
                                         const std::vector<std::size_t>& counts, bool ready,
                                         dealii::ConditionalOStream& log) {
  int rank = 0, n_ranks = 1;
  MPI_Comm_rank(communicator_, &rank);
  MPI_Comm_size(communicator_, &n_ranks);
  if (counts.size() != static_cast<std::size_t>(n_ranks) ||
      first + std::accumulate(counts.begin(), counts.end(), std::size_t{0}) != blocks.blocks.size())
    throw_error("fem: a deal of column blocks does not fit the blocks or the ranks");
  std::vector<int> owner;
  for (std::size_t r = 0; r < counts.size(); ++r) owner.insert(owner.end(), counts[r], static_cast<int>(r));
  bool solved = ready;
  for (std::size_t g = first; g < blocks.blocks.size() && solved; ++g) {
    if (owner[g - first] == rank) solved = solve_column_block(blocks, g, log);
  }
  if (n_ranks > 1) {
    // Every rank learns whether all solved; the ranks done first sleep through the wait instead
    // of spinning on the cores the others still solve on.
    int mine = solved ? 1 : 0, all = 0;
    MPI_Request request;
    MPI_Iallreduce(&mine, &all, 1, MPI_INT, MPI_MIN, communicator_, &request);
    wait_without_spinning(request);
    solved = all == 1;
    if (solved) gather_columns(blocks, first, owner);
  }
  if (!solved || rank != 0) return solved;
  for (std::size_t g = first; g < blocks.blocks.size(); ++g) {
    if (owner[g - first] != 0) solved_columns_ += static_cast<unsigned int>(3 * blocks.blocks[g].count);
  }
  return true;
}

bool BodyCompliance::solve_column_block(const ColumnBlocks& blocks, std::size_t g,
                                        dealii::ConditionalOStream& log) {
  const ColumnBlocks::Block& block = blocks.blocks[g];
  const std::vector<int>& nodes = blocks.nodes[block.body];
  Body& body = bodies_[block.body];
  const std::size_t n_surface = body.surface_nodes.size();
  const std::size_t k = 3 * block.count;
  std::vector<double> rhs(k * static_cast<std::size_t>(body.n_free), 0.0);
  for (std::size_t q = 0; q < block.count; ++q) {
    for (unsigned int c = 0; c < 3; ++c) {
      const PetscInt r =
          body.free_index[body_index_of_dof_[node_dofs_[nodes[block.first + q]][c]]];
      if (r >= 0) rhs[(3 * q + c) * body.n_free + r] = 1.0;
    }
  }
  if (!solve_block(body, rhs, k, log)) return false;
  for (std::size_t q = 0; q < block.count; ++q) {
    std::vector<double>& out = body.node_columns[surface_index_[nodes[block.first + q]]];
    out.assign(9 * n_surface, 0.0);
    for (unsigned int c = 0; c < 3; ++c) {
      const double* x = rhs.data() + (3 * q + c) * body.n_free;
      double* column = out.data() + c * 3 * n_surface;
      for (std::size_t s = 0; s < n_surface; ++s) {
        for (unsigned int d = 0; d < 3; ++d) {
          const PetscInt r =
              body.free_index[body_index_of_dof_[node_dofs_[body.surface_nodes[s]][d]]];
          column[3 * s + d] = r >= 0 ? x[r] : 0.0;
        }
      }
    }
  }
  columns_solved_here_ += static_cast<unsigned int>(k);
  solved_columns_ += static_cast<unsigned int>(k);
  return true;
}

void BodyCompliance::gather_columns(const ColumnBlocks& blocks, std::size_t first,
                                    const std::vector<int>& owner) {
  // A block's columns travel as its nodes' node_columns one after the other (9 per surface
  // node of the body each). Round j carries each rank's j-th block.
  int rank = 0, n_ranks = 1;
  MPI_Comm_rank(communicator_, &rank);
  MPI_Comm_size(communicator_, &n_ranks);
  const std::size_t ranks = static_cast<std::size_t>(n_ranks);
  std::vector<std::vector<std::size_t>> owned(ranks);
  for (std::size_t i = 0; i < owner.size(); ++i) owned[static_cast<std::size_t>(owner[i])].push_back(first + i);
  std::size_t rounds = 0;
  for (std::size_t r = 1; r < ranks; ++r) rounds = std::max(rounds, owned[r].size());
  const auto block_size = [&](std::size_t g) {
    return blocks.blocks[g].count * 9 * bodies_[blocks.blocks[g].body].surface_nodes.size();
  };
  const auto node_columns_of = [&](std::size_t g, std::size_t q) -> std::vector<double>& {
    const ColumnBlocks::Block& block = blocks.blocks[g];
    const int node = blocks.nodes[block.body][block.first + q];
    return bodies_[block.body].node_columns[surface_index_[node]];
  };
  std::vector<double> send, receive;
  std::vector<int> counts(ranks), offsets(ranks);
  for (std::size_t round = 0; round < rounds; ++round) {
    send.clear();
    const std::vector<std::size_t>& mine = owned[static_cast<std::size_t>(rank)];
    if (rank != 0 && round < mine.size()) {
      const std::size_t g = mine[round];
      send.reserve(block_size(g));
      for (std::size_t q = 0; q < blocks.blocks[g].count; ++q) {
        std::vector<double>& columns = node_columns_of(g, q);
        send.insert(send.end(), columns.begin(), columns.end());
        std::vector<double>().swap(columns);  // rank 0 keeps them
      }
    }
    int total = 0;
    for (std::size_t r = 0; r < ranks; ++r) {
      counts[r] = r == 0 || round >= owned[r].size() ? 0 : static_cast<int>(block_size(owned[r][round]));
      offsets[r] = total;
      total += counts[r];
    }
    if (rank == 0) receive.resize(static_cast<std::size_t>(total));
    MPI_Gatherv(send.data(), static_cast<int>(send.size()), MPI_DOUBLE, receive.data(),
                counts.data(), offsets.data(), MPI_DOUBLE, 0, communicator_);
    if (rank != 0) continue;
    for (std::size_t r = 1; r < ranks; ++r) {
      if (round >= owned[r].size()) continue;
      const std::size_t g = owned[r][round];
      const std::size_t per_node = 9 * bodies_[blocks.blocks[g].body].surface_nodes.size();
      const double* data = receive.data() + offsets[r];
      for (std::size_t q = 0; q < blocks.blocks[g].count; ++q)
        node_columns_of(g, q).assign(data + q * per_node, data + (q + 1) * per_node);
    }
  }
}

const double* BodyCompliance::columns(int node) const {
  const std::vector<double>& out = bodies_[body_of_node_[node]].node_columns[surface_index_[node]];
  return out.empty() ? nullptr : out.data();
}

dealii::Tensor<1, 3> BodyCompliance::translation_lifting(std::size_t b, std::size_t k,
                                                         unsigned int c, std::size_t s) const {
  const Body& body = bodies_[b];
  dealii::Tensor<1, 3> value;
  const NodeDofs& dofs = node_dofs_[body.surface_nodes[s]];
  for (unsigned int d = 0; d < 3; ++d)
    value[d] = body.liftings[3 * k + c][body_index_of_dof_[dofs[d]]];
  return value;
}

dealii::Tensor<1, 3> BodyCompliance::extra_lifting(std::size_t b, std::size_t s) const {
  const Body& body = bodies_[b];
  dealii::Tensor<1, 3> value;
  if (body.extra.empty()) return value;
  const NodeDofs& dofs = node_dofs_[body.surface_nodes[s]];
  for (unsigned int d = 0; d < 3; ++d) value[d] = body.extra[body_index_of_dof_[dofs[d]]];
  return value;
}

void BodyCompliance::lifting_reactions(std::size_t n_rigid_bodies,
                                       std::vector<std::vector<dealii::Tensor<2, 3>>>& a,
                                       std::vector<dealii::Tensor<1, 3>>& r0) const {
  a.assign(n_rigid_bodies, std::vector<dealii::Tensor<2, 3>>(n_rigid_bodies));
  r0.assign(n_rigid_bodies, dealii::Tensor<1, 3>());
  for (const Body& body : bodies_) {
    const dealii::Tensor<2, 3>& q = body.rotation;
    for (std::size_t i = 0; i < body.lifted_bodies.size(); ++i) {
      const int r = body.lifted_bodies[i];
      r0[r] += q * body.r0[i];
      for (std::size_t j = 0; j < body.lifted_bodies.size(); ++j)
        a[r][body.lifted_bodies[j]] += q * body.a[i][j] * dealii::transpose(q);
    }
  }
}

bool BodyCompliance::recover(const std::vector<dealii::Tensor<1, 3>>& translations,
                             const std::vector<dealii::Tensor<1, 3>>& node_force,
                             dealii::Vector<double>& displacement,
                             dealii::ConditionalOStream& log) {
  for (Body& body : bodies_) {
    const dealii::Tensor<2, 3> qt = dealii::transpose(body.rotation);
    std::vector<double> rhs(body.n_free, 0.0);
    bool loaded = false;
    for (const int node : body.surface_nodes) {
      const dealii::Tensor<1, 3> f = qt * node_force[node];
      for (unsigned int c = 0; c < 3; ++c) {
        const PetscInt r = body.free_index[body_index_of_dof_[node_dofs_[node][c]]];
        if (r >= 0 && f[c] != 0.0) {
          rhs[r] = f[c];
          loaded = true;
        }
      }
    }
    if (loaded && !solve_block(body, rhs, 1, log)) return false;
    std::vector<dealii::Tensor<1, 3>> t_body;
    for (const int r : body.lifted_bodies) t_body.push_back(qt * translations[r]);
    for (const int node : body.nodes) {
      dealii::Tensor<1, 3> u;
      for (unsigned int d = 0; d < 3; ++d) {
        const int i = body_index_of_dof_[node_dofs_[node][d]];
        const PetscInt r = body.free_index[i];
        double value = (r >= 0 && loaded) ? rhs[r] : 0.0;
        for (std::size_t k = 0; k < body.lifted_bodies.size(); ++k) {
          for (unsigned int c = 0; c < 3; ++c) value += t_body[k][c] * body.liftings[3 * k + c][i];
        }
        if (!body.extra.empty()) value += body.extra[i];
        u[d] = value;
      }
      const dealii::Tensor<1, 3> global = body.rotation * u;
      for (unsigned int d = 0; d < 3; ++d) displacement[node_dofs_[node][d]] = global[d];
    }
  }
  return true;
}

}  // namespace hipfai::fem
