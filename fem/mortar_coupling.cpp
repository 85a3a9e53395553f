#include "fem/mortar_coupling.h"

#include "core/error.h"
#include "fem/boundary_projection.h"
#include "fem/face_patch.h"
#include "fem/mortar_segments.h"
#include "fem/thread_chunks.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>

namespace hipfai::fem {

using dealii::types::global_dof_index;

namespace {

SlaveBoundaryNodes gather_pair_nodes(const ElasticSystem& system, unsigned int p,
                            dealii::types::boundary_id slave_boundary_id) {
  SlaveBoundaryNodes out;
  out.boundary_id = slave_boundary_id;
  const dealii::FESystem<3>& fe = system.fe();
  dealii::FEFaceValues<3> face_values(system.mapping(), fe, dealii::QGauss<2>(fe.degree + 1),
                                      dealii::update_values | dealii::update_JxW_values);
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  for (const auto& cell : system.dof_handler().active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    for (const unsigned int face_no : cell->face_indices()) {
      const auto face = cell->face(face_no);
      if (!face->at_boundary() || face->boundary_id() != slave_boundary_id) continue;
      face_values.reinit(cell, face_no);
      for (unsigned int i = 0; i < dofs.size(); ++i) {
        if (!system.support_on_face(face_no, i)) continue;
        if (system.component_of(i) != 0) continue;
        auto [it, inserted] = out.node_of_dof.try_emplace(dofs[i], out.nodes.size());
        if (inserted) {
          SlaveNode node;
          node.pair = p;
          for (unsigned int c = 0; c < 3; ++c)
            node.dofs[c] = dofs[system.system_index(system.base_of(i), c)];
          node.position = system.support_points()[dofs[i]];
          out.nodes.push_back(node);
        }
        double area = 0.0;
        for (unsigned int q = 0; q < face_values.n_quadrature_points; ++q) {
          area += face_values.shape_value(i, q) * face_values.JxW(q);
        }
        out.nodes[it->second].area += area;
      }
    }
  }
  return out;
}

// The shape functions of a tensor-product Lagrange element (FE_Q: support points on a grid),
// evaluated as products of 1D Lagrange polynomials on the grid's coordinates: the mortar
// integration asks for them at every segment point, where the generic
// FiniteElement::shape_value goes through several virtual layers per call.
class TensorLagrange {
 public:
  explicit TensorLagrange(const dealii::FiniteElement<3>& fe) {
    const std::vector<dealii::Point<3>>& points = fe.get_unit_support_points();
    for (const dealii::Point<3>& p : points) nodes_.push_back(p[0]);
    std::sort(nodes_.begin(), nodes_.end());
    nodes_.erase(std::unique(nodes_.begin(), nodes_.end(),
                             [](double a, double b) { return std::abs(a - b) < 1e-12; }),
                 nodes_.end());
    for (const dealii::Point<3>& p : points) {
      std::array<unsigned int, 3> index{};
      for (unsigned int d = 0; d < 3; ++d) {
        const auto it = std::min_element(nodes_.begin(), nodes_.end(), [&](double a, double b) {
          return std::abs(a - p[d]) < std::abs(b - p[d]);
        });
        index[d] = static_cast<unsigned int>(it - nodes_.begin());
      }
      index_.push_back(index);
    }
  }
  // Values of the 1D polynomials at the coordinates of `p`, for value().
  void at(const dealii::Point<3>& p, std::array<std::array<double, 8>, 3>& l) const {
    for (unsigned int d = 0; d < 3; ++d) {
      for (std::size_t k = 0; k < nodes_.size(); ++k) {
        double v = 1.0;
        for (std::size_t m = 0; m < nodes_.size(); ++m) {
          if (m != k) v *= (p[d] - nodes_[m]) / (nodes_[k] - nodes_[m]);
        }
        l[d][k] = v;
      }
    }
  }
  // The piecewise-linear hats on the same grid (1 at their node, 0 at the neighbours), for
  // value(): the bilinear functions of the element's sub-grid, never negative. A coordinate a
  // round-off outside the cell (a face's own, 0 or 1) counts as on it.
  void hats_at(const dealii::Point<3>& p, std::array<std::array<double, 8>, 3>& l) const {
    for (unsigned int d = 0; d < 3; ++d) {
      const double x = std::clamp(p[d], nodes_.front(), nodes_.back());
      std::size_t k = 0;  // the grid interval [nodes_[k], nodes_[k + 1]] holding x
      while (k + 2 < nodes_.size() && x > nodes_[k + 1]) ++k;
      l[d].fill(0.0);
      const double t = (x - nodes_[k]) / (nodes_[k + 1] - nodes_[k]);
      l[d][k] = 1.0 - t;
      l[d][k + 1] = t;
    }
  }
  double value(unsigned int i, const std::array<std::array<double, 8>, 3>& l) const {
    return l[0][index_[i][0]] * l[1][index_[i][1]] * l[2][index_[i][2]];
  }
  std::size_t n_nodes() const { return nodes_.size(); }

 private:
  std::vector<double> nodes_;
  std::vector<std::array<unsigned int, 3>> index_;  // per shape function: its grid node
};

// Mortar integrals of the slave nodes against a deformable master, per node: M_sj per component
// (keyed by master dof), the covered part of D_s, the integral of psi_s (x_s - x_m) and the
// covered part of the integral of psi_s (the gap's weight, fem/mortar_coupling.h).
struct MortarIntegrals {
  std::vector<std::array<std::map<global_dof_index, double>, 3>> mortar;
  std::vector<dealii::Tensor<1, 3>> weighted_gap;
  std::vector<double> covered;      // integral of phi_s over the covered part
  std::vector<double> gap_covered;  // integral of psi_s over the covered part
};

MortarIntegrals integrate_mortar(const ElasticSystem& system, const BoundaryProjector& projector,
                                 const std::vector<FacePatch>& slave_faces,
                                 const SlaveBoundaryNodes& pair_nodes,
                                 const ContactSearchSettings& settings) {
  const std::size_t count = pair_nodes.nodes.size();
  MortarIntegrals out;
  out.mortar.resize(count);
  out.weighted_gap.assign(count, dealii::Tensor<1, 3>());
  out.covered.assign(count, 0.0);
  out.gap_covered.assign(count, 0.0);
  MortarSegmentOptions segment_options;
  segment_options.search_radius_mm = settings.search_radius_mm;
  segment_options.tangent_plane_cull = settings.tangent_plane_cull;
  const MortarSegmenter segmenter(projector.faces(), segment_options);
  const dealii::FESystem<3>& fe = system.fe();
  const TensorLagrange base(fe.base_element(0));
  if (base.n_nodes() > 8 || base.n_nodes() * base.n_nodes() * base.n_nodes() !=
                                fe.base_element(0).n_dofs_per_cell()) {
    throw_error("fem: mortar integration needs a tensor-product Lagrange element (FE_Q) of "
                "degree 7 or less");
  }
  // The slave faces are integrated independently (threads), each into small dense blocks per
  // master face it sees; the blocks are then added into the sparse rows in face order, so the
  // sums do not depend on the number of threads.
  struct Block {
    const FacePatch* master = nullptr;      // the master face the block couples to
    std::vector<unsigned int> master_base;  // base indices of the master face's nodes
    std::vector<double> m;                  // [slave node][master node]
  };
  struct FaceResult {
    std::vector<unsigned int> slave_base;   // base indices of the slave face's nodes
    std::vector<double> covered;            // per slave node
    std::vector<double> gap_covered;        // per slave node
    std::vector<dealii::Tensor<1, 3>> gap;  // per slave node
    std::vector<Block> blocks;              // one per master face seen, in integration order
  };
  const auto face_base_indices = [&](unsigned int face_no) {
    std::vector<unsigned int> indices;
    for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) {
      if (system.support_on_face(face_no, i) && system.component_of(i) == 0)
        indices.push_back(system.base_of(i));
    }
    return indices;
  };
  std::vector<FaceResult> face_results(slave_faces.size());
  auto integrate_faces = [&](std::size_t first, std::size_t last) {
    for (std::size_t f = first; f < last; ++f) {
      const FacePatch& slave = slave_faces[f];
      FaceResult& result = face_results[f];
      result.slave_base = face_base_indices(slave.face_no);
      const std::size_t ns = result.slave_base.size();
      result.covered.assign(ns, 0.0);
      result.gap_covered.assign(ns, 0.0);
      result.gap.assign(ns, dealii::Tensor<1, 3>());
      std::vector<double> slave_values(ns);
      std::array<std::array<double, 8>, 3> slave_l{}, master_l{}, hat_l{};
      for (const MortarPoint& point : segmenter.integrate(slave)) {
        base.at(point.slave_unit_point, slave_l);
        base.hats_at(point.slave_unit_point, hat_l);
        base.at(point.master_unit_point, master_l);
        if (result.blocks.empty() || result.blocks.back().master != point.master) {
          Block block;
          block.master = point.master;
          block.master_base = face_base_indices(point.master->face_no);
          block.m.assign(ns * block.master_base.size(), 0.0);
          result.blocks.push_back(std::move(block));
        }
        Block& block = result.blocks.back();
        const std::size_t nm = block.master_base.size();
        const dealii::Tensor<1, 3> separation = point.slave_point_mm - point.master_point_mm;
        for (std::size_t a = 0; a < ns; ++a) {
          slave_values[a] =
              base.value(result.slave_base[a], slave_l) * point.jxw;
          result.covered[a] += slave_values[a];
          const double hat = base.value(result.slave_base[a], hat_l) * point.jxw;
          result.gap_covered[a] += hat;
          result.gap[a] += hat * separation;
        }
        for (std::size_t b = 0; b < nm; ++b) {
          const double value = base.value(block.master_base[b], master_l);
          for (std::size_t a = 0; a < ns; ++a) block.m[a * nm + b] += slave_values[a] * value;
        }
      }
    }
  };
  // Faces opposite the master cost far more than the rest: blocks taken dynamically.
  parallel_blocks(slave_faces.size(), static_cast<int>(settings.n_threads), 8, integrate_faces);

  for (std::size_t f = 0; f < slave_faces.size(); ++f) {
    const FaceResult& result = face_results[f];
    const std::vector<global_dof_index>& dofs = slave_faces[f].dofs;
    std::vector<std::size_t> local(result.slave_base.size());
    for (std::size_t a = 0; a < local.size(); ++a) {
      local[a] = pair_nodes.node_of_dof.at(dofs[system.system_index(result.slave_base[a], 0)]);
      out.covered[local[a]] += result.covered[a];
      out.gap_covered[local[a]] += result.gap_covered[a];
      out.weighted_gap[local[a]] += result.gap[a];
    }
    for (const Block& block : result.blocks) {
      const std::vector<global_dof_index>& master_dofs = block.master->dofs;
      const std::size_t nm = block.master_base.size();
      for (std::size_t a = 0; a < local.size(); ++a) {
        for (std::size_t b = 0; b < nm; ++b) {
          const double value = block.m[a * nm + b];
          for (unsigned int c = 0; c < 3; ++c) {
            out.mortar[local[a]][c][master_dofs[system.system_index(block.master_base[b], c)]] +=
                value;
          }
        }
      }
    }
  }
  return out;
}

// The slave component with the largest normal share that is still free; with less than 0.3 the
// constraint would be ill-conditioned (the node sits on a wall parallel to n). False: none.
bool choose_constrained_component(SlaveNode& node, const std::vector<bool>& fixed_dof) {
  double best = 0.3;
  bool found = false;
  for (unsigned int c = 0; c < 3; ++c) {
    if (fixed_dof[node.dofs[c]]) continue;
    if (std::abs(node.normal[c]) > best) {
      best = std::abs(node.normal[c]);
      node.constrained_component = c;
      found = true;
    }
  }
  return found;
}

}  // namespace

std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const std::vector<bool>& fixed_dof,
                                           bool tangent_plane_cull) {
  ContactSurfaces surfaces;
  surfaces.update(system, model);
  return collect_slave_nodes(system, model, surfaces, fixed_dof, tangent_plane_cull);
}

std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const ContactSurfaces& surfaces,
                                           const std::vector<bool>& fixed_dof,
                                           bool tangent_plane_cull) {
  return collect_slave_nodes(system, model, surfaces, fixed_dof,
                             {contact_search_radius(system.diameter()),
                              system.threads(), tangent_plane_cull});
}

std::vector<SlaveBoundaryNodes> slave_boundary_nodes(const ElasticSystem& system,
                                                     const ContactModel& model) {
  std::vector<SlaveBoundaryNodes> out;
  for (unsigned int p = 0; p < model.contact_pairs.size(); ++p) {
    const dealii::types::boundary_id id = model.contact_pairs[p].slave_boundary_id;
    out.push_back(gather_pair_nodes(system, p, id));
    if (out.back().nodes.empty()) {
      throw_error("fem model: contact pair ", p, ": slave boundary ", static_cast<int>(id),
                  " has no faces");
    }
  }
  return out;
}

bool slave_boundaries_of(const std::vector<SlaveBoundaryNodes>& slaves, const ContactModel& model) {
  if (slaves.size() != model.contact_pairs.size()) return false;
  for (std::size_t p = 0; p < slaves.size(); ++p)
    if (slaves[p].boundary_id != model.contact_pairs[p].slave_boundary_id) return false;
  return true;
}

std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const ContactSurfaces& surfaces,
                                           const std::vector<bool>& fixed_dof,
                                           const ContactSearchSettings& settings) {
  return collect_slave_nodes(system, model, surfaces, slave_boundary_nodes(system, model),
                             fixed_dof, settings);
}

std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const ContactSurfaces& surfaces,
                                           const std::vector<SlaveBoundaryNodes>& slaves,
                                           const std::vector<bool>& fixed_dof,
                                           const ContactSearchSettings& settings) {
  if (!slave_boundaries_of(slaves, model))
    throw_error("fem: the slave boundaries given are not the model's contact pairs'");
  std::vector<SlaveNode> nodes;
  const double search_radius_mm = settings.search_radius_mm;
  for (unsigned int p = 0; p < model.contact_pairs.size(); ++p) {
    const ContactPair& pair = model.contact_pairs[p];
    std::unique_ptr<BoundaryProjector> projector;
    if (pair.master_rigid_body < 0) {
      projector = std::make_unique<BoundaryProjector>(system.fe(),
                                                      surfaces.faces(pair.master_boundary_id));
      if (projector->n_faces() == 0) {
        throw_error("fem model: contact pair ", p, ": master boundary ",
                    static_cast<int>(pair.master_boundary_id), " has no faces");
      }
    }
    const SlaveBoundaryNodes& pair_nodes = slaves[p];
    MortarIntegrals integrals;
    if (projector)
      integrals = integrate_mortar(system, *projector, surfaces.faces(pair.slave_boundary_id),
                                   pair_nodes, settings);

    // Project, choose the constrained component, drop nodes that cannot be constrained.
    for (std::size_t local = 0; local < pair_nodes.nodes.size(); ++local) {
      SlaveNode node = pair_nodes.nodes[local];
      if (pair.master_rigid_body >= 0) {
        // The surface is defined in the body's frame: query there, map the answer back.
        const RigidBody& body = model.rigid_bodies[pair.master_rigid_body];
        const dealii::Point<3>& c = body.rotation_center_mm;
        const SurfacePoint closest =
            body.surface->closest_point(c + dealii::transpose(body.rotation) * (node.position - c));
        const dealii::Point<3> master_point = c + body.rotation * (closest.point_mm - c);
        node.normal = body.rotation * closest.normal;
        node.rigid_body = pair.master_rigid_body;
        node.initial_gap = (node.position - master_point) * node.normal;
      } else {
        const BoundaryProjection projection = projector->closest(node.position, search_radius_mm);
        if (!projection.found) continue;  // nothing opposite: this node cannot touch
        // Barely covered nodes (the master ends just past them) would give an ill-scaled row.
        const double covered = integrals.covered[local];
        // So are nodes whose own hat sees no master (psi_s's support is the part of phi_s's
        // nearest the node): the master ends between them and their neighbours.
        if (!(covered > 1e-6 * node.area)) continue;
        const double gap_covered = integrals.gap_covered[local];
        if (!(gap_covered > 1e-6 * node.area)) continue;
        node.normal = projection.normal;
        for (unsigned int c = 0; c < 3; ++c) {
          for (const auto& [dof, value] : integrals.mortar[local][c]) {
            if (value != 0.0) node.master[c].emplace_back(dof, value / covered);
          }
        }
        node.initial_gap = integrals.weighted_gap[local] * node.normal / gap_covered;
      }
      if (choose_constrained_component(node, fixed_dof)) nodes.push_back(node);
    }
  }
  return nodes;
}

}  // namespace hipfai::fem
