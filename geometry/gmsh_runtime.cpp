#include "geometry/gmsh_runtime.h"

#include "core/error.h"

#include <gmsh.h>

namespace hipfai::geometry {
namespace {

void start_gmsh() {
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
}

struct GmshRuntime {
  GmshRuntime() { start_gmsh(); }
  ~GmshRuntime() { gmsh::finalize(); }
  GmshRuntime(const GmshRuntime&) = delete;
  GmshRuntime& operator=(const GmshRuntime&) = delete;
};

std::mutex& gmsh_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

std::unique_lock<std::mutex> lock_gmsh() {
  std::unique_lock<std::mutex> lock(gmsh_mutex());
  static GmshRuntime runtime;  // constructed under the lock, destroyed at exit
  return lock;
}

void reset_gmsh_locked(const std::unique_lock<std::mutex>& held) {
  if (!held.owns_lock() || held.mutex() != &gmsh_mutex()) {
    throw_error("gmsh_runtime: reset_gmsh_locked needs the lock from lock_gmsh()");
  }
  // The runtime exists: the lock was taken through lock_gmsh(), which constructed it.
  try {
    gmsh::finalize();
  } catch (...) {
  }
  start_gmsh();
}

}  // namespace hipfai::geometry
