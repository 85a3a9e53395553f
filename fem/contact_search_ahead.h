// hipfai — the contact searches of a motion's next poses, run while the current pose is solved.
//
// The contact search of a run depends on where the bodies are placed (the rigid bodies'
// rotations), not on how the previous run ended: the femur's translation enters the gaps
// linearly (fem/condensed_contact.h), so the searches of the poses to come can run while a pose
// is being solved. Their inputs are read from the system without moving the mesh: the master
// faces are the contact surfaces turned to each pose (ContactSurfaces::predicted), the search
// radius is the diameter of that placement (ElasticSystem::diameter_if_placed), and the slave
// surfaces, dofs and support points are the current ones, which is exact only if the slave
// bodies do not move. So a run uses a search made ahead only after checking, bit for bit, that
// it searched exactly that run's input: the same model geometry, the faces ContactSurfaces::update
// gave, the radius, the fixed dofs and the slave nodes' support points. Any difference (a
// cutback's other pose, a moved slave body, a face remade) and the run searches anew. Either way
// the nodes are those the run's own search would give, so the answers do not change; only the
// time does. The first run's long solve (the compliance columns) hides most of the searches.
//
// The searches run on a thread of their own, one after the other, and read nothing of the system
// once planned: the slave boundaries' nodes are taken from the mesh when the first search is
// planned (slave_boundary_nodes), the faces carry their dofs, and each search holds its own copy
// of everything else. So the caller moves the mesh, renumbers its dofs and solves while they run;
// it waits only when it takes a search still in progress. The slave nodes kept are checked against
// the mesh at every take (their dofs' support points); when they differ the run searches itself
// and they are taken anew at the next plan.
#pragma once

#include "fem/contact_model.h"
#include "fem/contact_surfaces.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <condition_variable>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace hipfai::fem {

class ContactSearchAhead {
 public:
  ContactSearchAhead();
  ~ContactSearchAhead();
  ContactSearchAhead(const ContactSearchAhead&) = delete;
  ContactSearchAhead& operator=(const ContactSearchAhead&) = delete;

  // The placements of the runs to come, in order: searches already made or queued for the same
  // placements are kept, the others queued (the faces of `surfaces`, brought to the system's
  // current placement, turned to each), and searches no longer expected dropped. The thread
  // starts on them at once.
  void plan(const ElasticSystem& system, const ContactSurfaces& surfaces,
            const std::vector<ContactModel>& upcoming, const std::vector<bool>& fixed_dof,
            bool tangent_plane_cull);
  // The nodes searched ahead for this run if its search searched exactly this run's input (the
  // system placed and set up for `model`, `surfaces` updated to it), after waiting for it if it
  // is in progress; nothing otherwise (the caller then searches; a search not yet started is
  // dropped, not waited for). Searches of placements before it are dropped.
  std::optional<std::vector<SlaveNode>> take(const ElasticSystem& system,
                                             const ContactSurfaces& surfaces,
                                             const ContactModel& model,
                                             const std::vector<bool>& fixed_dof,
                                             bool tangent_plane_cull);
  // The work left to the searching thread: the searches queued or in progress times the mean
  // CPU time of the searches it has finished (its own thread's clock, so a search slowed by the
  // solves beside it counts only its own work), in seconds; 0 when none is left, and
  // std::nullopt while searches are left but none has finished yet.
  std::optional<double> remaining_seconds();

 private:
  struct Search;
  void work();

  // The slave boundaries' nodes every queued search reads (null until the first plan, or after
  // a take found them moved).
  std::shared_ptr<const std::vector<SlaveBoundaryNodes>> slaves_;
  // In the order of the runs to come; the thread holds the one it searches, so dropping it from
  // the queue is safe.
  std::list<std::shared_ptr<Search>> queue_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool stop_ = false;
  // The searches finished and their CPU time, seconds.
  std::size_t searched_ = 0;
  double search_seconds_ = 0.0;
  std::thread thread_;  // started by the first plan()
};

}  // namespace hipfai::fem
