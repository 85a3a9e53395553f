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
// The searches run on a thread of their own, one at a time, only between resume() and pause():
// the caller must pause before it changes the mesh, the dofs or the system's placement
// (ContactProblem resumes after its own search and pauses at the end of every run).
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
  // current placement, turned to each), and searches no longer expected dropped. Paused or not
  // started: call resume() to let the searches run.
  void plan(const ElasticSystem& system, const ContactSurfaces& surfaces,
            const std::vector<ContactModel>& upcoming, const std::vector<bool>& fixed_dof,
            bool tangent_plane_cull);
  // Lets the thread search the queued placements, one after the other.
  void resume();
  // Lets the search in progress finish and starts no other; returns the seconds waited.
  double pause();
  // The nodes searched ahead for this run if the search is finished and searched exactly this
  // run's input (the system placed and set up for `model`, `surfaces` updated to it); nothing
  // otherwise (the caller then searches). Searches of placements before it are dropped. Call
  // while paused.
  std::optional<std::vector<SlaveNode>> take(const ElasticSystem& system,
                                             const ContactSurfaces& surfaces,
                                             const ContactModel& model,
                                             const std::vector<bool>& fixed_dof,
                                             bool tangent_plane_cull);

 private:
  struct Search;
  void work();

  const ElasticSystem* system_ = nullptr;
  std::vector<bool> fixed_dof_;
  dealii::types::global_dof_index n_dofs_ = 0;
  std::list<Search> queue_;  // in the order of the runs to come; stable addresses for the thread
  std::mutex mutex_;
  std::condition_variable changed_;
  bool paused_ = true, stop_ = false;
  std::thread thread_;  // started by the first plan()
};

}  // namespace hipfai::fem
