// hipfai — each deformable body factorised once in its own frame, and the compliance of its
// contact surface.
//
// The bodies are linear elastic, small strain, bonded to rigid bones: a body bonded to a bone
// that rotates is rotated rigidly with it (fem/elastic_system.h), so in the frame it had when it
// was factorised its stiffness is the same at every step of a motion. With Q the block-diagonal
// rotation from that frame to the current one, K = Q K0 Q^T and K^-1 = Q K0^-1 Q^T. So each
// body's stiffness, restricted to its free dofs (not bonded, not on a symmetry plane), is
// factorised (MUMPS Cholesky) once, and reused for every later run while the body stays
// the same up to that rotation: same dofs, same fixed dofs, same material, and its support
// points the rotated ones (checked on every run; otherwise the body is factorised anew).
//
// What the contact solve needs from a body (fem/condensed_contact.h):
//  - compliance columns: K0^-1 e_j for the dofs j of a contact-surface node, kept only at the
//    body's contact-surface dofs (the rows any contact constraint can read). Computed when a
//    node first carries an active constraint (block solves of 48 nodes for the nodes new to an
//    iteration; on several ranks blocks may be dealt to the ranks, share_column_blocks) and kept for
//    every later run;
//  - liftings: the displacement of the whole body for a unit translation of each rigid body it
//    is bonded to (bonded dofs at the translation, the rest at equilibrium), and for the extra
//    prescribed displacement of its bonded boundaries; with their reactions (the translation
//    stiffness A = L^T K L, zero for a body bonded to one bone);
//  - recovery: the displacement of the whole body under given forces at its surface dofs.
// Frames: every vector handed in or out is in the current (global) frame, except where a
// function says "body frame" (the frame of the factorisation).
// Units: mm, N, MPa.
#pragma once

#include "fem/contact_constraints.h"
#include "fem/contact_model.h"
#include "fem/elastic_system.h"
#include "fem/petsc_solvers.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/types.h>
#include <deal.II/lac/vector.h>

#include <petscmat.h>

#include <mpi.h>

#include <array>
#include <memory>
#include <vector>

namespace hipfai::fem {

// A support point's three displacement dofs (x, y, z), as the condensed solve addresses them.
using NodeDofs = std::array<dealii::types::global_dof_index, 3>;

class BodyCompliance {
 public:
  // `communicator`: the ranks that share the column solves (share_column_blocks); a rank that
  // solves columns factorises every body in the same run as rank 0 (the same frame).
  explicit BodyCompliance(MPI_Comm communicator = MPI_COMM_SELF) : communicator_(communicator) {}
  ~BodyCompliance();
  BodyCompliance(const BodyCompliance&) = delete;
  BodyCompliance& operator=(const BodyCompliance&) = delete;

  // Prepares a run: the nodes of the system, each body's rotation since its factorisation, and
  // which bodies must be factorised anew (first run, other dofs, fixed dofs, material or
  // shape). Throws hipfai::Error for hanging nodes (not supported by this solver).
  void begin_run(const ElasticSystem& system, const ContactConstraints& constraints,
                 const ContactModel& model);
  // True when a body must be factorised in this run: the cell matrices must then be current.
  bool needs_factorisation() const;
  // True when every body must be factorised in this run (the first run, for one).
  bool needs_every_factorisation() const;
  // Factorises the bodies that need it, or with `every_body` all of them (reads the system's
  // cell matrices): a rank that solves columns for rank 0 needs its factors in rank 0's frames.
  // False, with the reason on `log`, when a factorisation failed.
  bool factorise(const ElasticSystem& system, const ContactConstraints& constraints,
                 const ContactModel& model, dealii::TimerOutput& timer,
                 dealii::ConditionalOStream& log, bool every_body = false);

  // The node of a dof (index into node_dofs), -1 for none.
  int node_of_dof(dealii::types::global_dof_index dof) const { return node_of_dof_[dof]; }
  const NodeDofs& node_dofs(int node) const { return node_dofs_[node]; }
  std::size_t n_nodes() const { return node_dofs_.size(); }
  // The body of a node (index into ContactModel::bodies).
  int body_of_node(int node) const { return body_of_node_[node]; }
  // Position of a node among its body's contact-surface nodes, -1 when not on the surface.
  int surface_index(int node) const { return surface_index_[node]; }
  // Contact-surface nodes of body b.
  std::size_t n_surface_nodes(std::size_t b) const { return bodies_[b].surface_nodes.size(); }
  std::size_t n_bodies() const { return bodies_.size(); }
  // Rotation from body b's factorisation frame to this run's frame.
  const dealii::Tensor<2, 3>& rotation(std::size_t b) const { return bodies_[b].rotation; }

  // Makes sure the compliance columns of these nodes exist (one block solve per block of the
  // missing ones, column_blocks), all on this rank. False when a solve failed.
  bool ensure_columns(const std::vector<int>& nodes, dealii::ConditionalOStream& log);
  // The nodes among `nodes` whose columns are not computed yet, ascending, each once. Throws
  // hipfai::Error for a node off every contact surface.
  std::vector<int> missing_columns(const std::vector<int>& nodes) const;

  // The missing nodes (from missing_columns) in blocks of 48: each body's in ascending order,
  // the blocks numbered body after body. A block is one MUMPS block solve of the body's factor;
  // its columns are the same bit for bit whichever rank solves it, in whichever order.
  struct ColumnBlocks {
    std::vector<std::vector<int>> nodes;  // per body, ascending
    struct Block {
      std::size_t body = 0;
      std::size_t first = 0;  // into nodes[body]
      std::size_t count = 0;
    };
    std::vector<Block> blocks;
  };
  ColumnBlocks column_blocks(const std::vector<int>& missing) const;
  // Solves block g on this rank and keeps its columns. False when the solve failed.
  bool solve_column_block(const ColumnBlocks& blocks, std::size_t g, dealii::ConditionalOStream& log);
  // Collective over the communicator (every rank with the same blocks, `first` and `counts`,
  // fem/column_deal.h): blocks first, first + 1, ... are dealt in contiguous runs, counts[r] of
  // them to rank r in rank order; each rank solves its own, and rank 0 gathers the others'
  // columns and keeps them (it solves the condensed problem); the other ranks keep none. False
  // on every rank when a solve failed on any, or a rank was not `ready` (its factorisation
  // failed). Throws hipfai::Error when the counts do not fit the blocks and the ranks.
  bool share_column_blocks(const ColumnBlocks& blocks, std::size_t first,
                           const std::vector<std::size_t>& counts, bool ready,
                           dealii::ConditionalOStream& log);
  // Body frame: the 3 columns of node `node` at body b's surface dofs, laid out as
  // [component c of the unit force][surface node][component of the displacement]; null when the
  // node's columns were not computed.
  const double* columns(int node) const;

  // Rigid bodies whose translation moves body b's bonded dofs.
  const std::vector<int>& bonded_rigid_bodies(std::size_t b) const {
    return bodies_[b].lifted_bodies;
  }
  // Body frame: displacement of surface node s of body b for a unit translation (body-frame
  // component c) of its k-th bonded rigid body.
  dealii::Tensor<1, 3> translation_lifting(std::size_t b, std::size_t k, unsigned int c,
                                           std::size_t s) const;
  // Body frame: displacement of surface node s of body b under the bonded boundaries' extra
  // displacement (zero when there is none).
  dealii::Tensor<1, 3> extra_lifting(std::size_t b, std::size_t s) const;
  // Global frame, summed over the bodies: the force the bonded dofs of rigid body r transmit for
  // the liftings alone, as (3 x 3) blocks A[r][r'] of the translations and the part r0[r] of
  // the extra displacement: transmitted_r = sum_r' A[r][r'] t_r' + r0[r].
  void lifting_reactions(std::size_t n_rigid_bodies,
                         std::vector<std::vector<dealii::Tensor<2, 3>>>& a,
                         std::vector<dealii::Tensor<1, 3>>& r0) const;

  // The displacement of every body (global frame, into `displacement`, every dof set) for the
  // rigid translations and the forces `surface_force` (global frame, per node of the system;
  // only surface nodes may carry force). False when a solve failed.
  bool recover(const std::vector<dealii::Tensor<1, 3>>& translations,
               const std::vector<dealii::Tensor<1, 3>>& node_force,
               dealii::Vector<double>& displacement, dealii::ConditionalOStream& log);

  // Counts since construction: factorisations, compliance columns solved by all ranks together
  // (as rank 0 counts them; another rank counts its own), and by this rank (the same on one
  // rank).
  unsigned int factorisations() const { return factorisations_; }
  unsigned int solved_columns() const { return solved_columns_; }
  unsigned int columns_solved_here() const { return columns_solved_here_; }

 private:
  struct Body {
    int rigid_body = -1;                    // the bone it rotates with (-1: none)
    std::vector<int> nodes;                 // its nodes
    std::vector<dealii::types::global_dof_index> dofs;  // its dofs (the nodes' x, y, z)
    std::vector<PetscInt> free_index;       // per entry of dofs: index among the free, or -1
    PetscInt n_free = 0;
    std::vector<int> surface_nodes;         // nodes on a contact boundary
    // The state it was factorised in: support points (frame of the factorisation), fixed dofs,
    // Lame constants, the rotation of its rigid body then, the extra displacement values.
    std::vector<dealii::Point<3>> factor_points;
    std::vector<bool> factor_fixed;
    std::pair<double, double> factor_lame{0.0, 0.0};
    dealii::Tensor<2, 3> factor_rotation;
    std::vector<double> factor_extra;       // per entry of dofs (body frame)
    bool partly_fixed_nodes = false;        // a node with 1 or 2 fixed components
    // The factor and its matrix's arrays (upper triangle, CSR).
    std::vector<PetscInt> row_start, columns;
    std::vector<double> values;
    Mat matrix = nullptr;
    std::unique_ptr<CholeskySolve> cholesky;
    // Liftings over all dofs (body frame): 3 per rigid body in lifted_bodies, then the extra.
    std::vector<int> lifted_bodies;
    std::vector<std::vector<double>> liftings;  // [3 k + c]
    std::vector<double> extra;                 // empty: no extra displacement
    // Reactions of the liftings at the bonded dofs of each lifted body (body frame):
    // a[k][k'](c, c') and r0[k](c).
    std::vector<std::vector<dealii::Tensor<2, 3>>> a;
    std::vector<dealii::Tensor<1, 3>> r0;
    // Compliance columns per surface node (empty: not computed), see columns().
    std::vector<std::vector<double>> node_columns;
    // This run.
    dealii::Tensor<2, 3> rotation;
    bool stale = true;
  };
  void release(Body& body);
  // A bonded dof of a body: index into its dofs, its rigid body's place in lifted_bodies (-1:
  // bonded to none), component and extra displacement.
  struct Held {
    int i;
    int k;
    unsigned int component;
    double extra;
  };
  // The body's bonded dofs and the data of its liftings (3 per rigid body it is bonded to, then
  // the extra displacement if any), over its dofs.
  struct BondedData {
    std::vector<Held> held;
    std::vector<std::vector<double>> data;
    bool has_extra = false;
  };
  bool factorise_body(std::size_t b, const ElasticSystem& system,
                      const ContactConstraints& constraints, const ContactModel& model,
                      dealii::ConditionalOStream& log);
  static void number_free_dofs(Body& body, const std::vector<bool>& fixed);
  BondedData bonded_data(std::size_t b, Body& body, const ContactConstraints& constraints);
  // Factorises the body's stiffness on its free dofs; `rhs` (n_lift x n_free) gets -K_fd d of
  // each lifting. Returns the body's cells.
  std::vector<dealii::DoFHandler<3>::active_cell_iterator> factorise_free_stiffness(
      std::size_t b, Body& body, const ElasticSystem& system, const BondedData& bonded,
      std::vector<double>& rhs);
  // The translation stiffness A and reaction r0 of the body's liftings (after they are solved).
  void add_lifting_reactions(Body& body, const ElasticSystem& system,
                             const std::vector<dealii::DoFHandler<3>::active_cell_iterator>& cells,
                             const BondedData& bonded);
  bool solve_block(Body& body, std::vector<double>& rhs, std::size_t k,
                   dealii::ConditionalOStream& log);
  // Rank 0 gets the columns of the blocks the other ranks solved (owner[g], for g from `first`),
  // a round of at most one block per rank at a time (so the buffer stays a few blocks large);
  // the other ranks drop theirs.
  void gather_columns(const ColumnBlocks& blocks, std::size_t first, const std::vector<int>& owner);

  std::vector<int> node_of_dof_;
  std::vector<NodeDofs> node_dofs_;
  std::vector<int> body_of_node_, surface_index_;
  // The connected piece of each node (nodes joined through their cells): a representative node.
  std::vector<int> piece_of_node_;
  std::vector<int> body_index_of_dof_;  // index into the body's dofs, -1 for none
  std::vector<Body> bodies_;
  std::size_t layout_key_ = 0;
  MPI_Comm communicator_;
  unsigned int factorisations_ = 0;
  unsigned int solved_columns_ = 0;
  unsigned int columns_solved_here_ = 0;
};

}  // namespace hipfai::fem
