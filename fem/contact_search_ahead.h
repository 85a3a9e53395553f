// hipfai — the contact search of a motion's next pose, run while the current pose is solved.
//
// The contact search of a run depends on where the bodies are placed (the rigid bodies'
// rotations), not on how the previous run ended: the femur's translation enters the gaps
// linearly (fem/condensed_contact.h), so the search of pose k+1 can run while pose k is being
// solved. Its inputs are read from the system without moving the mesh: the master faces are the
// contact surfaces turned to the next pose (ContactSurfaces::predicted), the search radius is
// the diameter of the next placement (ElasticSystem::diameter_if_placed), and the slave
// surfaces, dofs and support points are the current ones, which is exact only if the slave
// bodies do not move. So the next run uses the search only after checking, bit for bit, that it
// searched exactly that run's input: the same model geometry, the faces ContactSurfaces::update
// gave, the radius, the fixed dofs and the slave nodes' support points. Any difference (a
// cutback's other pose, a moved slave body, a face remade) and the next run searches anew.
// Either way the nodes are those the synchronous search would give, so the answers do not
// change; only the time does.
//
// The search ahead runs on its own thread; the caller must not change the mesh, the dofs or the
// system's placement until wait() returned (ContactProblem waits at the end of every run).
#pragma once

#include "fem/contact_model.h"
#include "fem/contact_surfaces.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <future>
#include <memory>
#include <optional>
#include <vector>

namespace hipfai::fem {

class ContactSearchAhead {
 public:
  ContactSearchAhead();
  ~ContactSearchAhead();
  ContactSearchAhead(const ContactSearchAhead&) = delete;
  ContactSearchAhead& operator=(const ContactSearchAhead&) = delete;

  // Starts searching the placement of `next` on another thread, with the faces of `surfaces`
  // (brought to the system's current placement) turned to it. Waits for a search still running.
  void start(const ElasticSystem& system, const ContactSurfaces& surfaces, const ContactModel& next,
             const std::vector<bool>& fixed_dof, bool tangent_plane_cull, std::size_t n_threads);
  // Waits for the search started, if any. Returns the seconds waited.
  double wait();
  // The nodes the finished search found if it searched exactly this run's input (the system
  // placed and set up for `model`, `surfaces` updated to it); nothing otherwise (the caller then
  // searches). Consumes the search either way.
  std::optional<std::vector<SlaveNode>> take(const ElasticSystem& system,
                                             const ContactSurfaces& surfaces,
                                             const ContactModel& model,
                                             const std::vector<bool>& fixed_dof,
                                             bool tangent_plane_cull);

  // Searches whose nodes a run used, and searches a run could not use.
  unsigned int used() const { return used_; }
  unsigned int discarded() const { return discarded_; }

 private:
  struct Search;
  std::unique_ptr<Search> search_;
  unsigned int used_ = 0, discarded_ = 0;
};

}  // namespace hipfai::fem
