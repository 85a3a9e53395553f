#include "geometry/gmsh_runtime.h"

#include <gmsh.h>

namespace hipfai::geometry {
namespace {

struct GmshRuntime {
  GmshRuntime() {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
  }
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

}  // namespace hipfai::geometry
