#include "geometry/gmsh_runtime.h"

#include "core/error.h"

#include <gmsh.h>
#include <gtest/gtest.h>

#include <mutex>
#include <string>
#include <vector>

namespace hipfai::geometry {
namespace {

TEST(GmshRuntime, ResetNeedsTheGmshLock) {
  std::mutex other;
  std::unique_lock<std::mutex> not_gmsh(other);
  EXPECT_THROW(reset_gmsh_locked(not_gmsh), Error);
  std::unique_lock<std::mutex> gmsh_lock = lock_gmsh();
  gmsh_lock.unlock();
  EXPECT_THROW(reset_gmsh_locked(gmsh_lock), Error);  // released: no longer held
}

TEST(GmshRuntime, ResetRestoresDefaultsAndAQuietTerminal) {
  const std::unique_lock<std::mutex> gmsh_lock = lock_gmsh();
  double terminal = -1.0;
  gmsh::option::getNumber("General.Terminal", terminal);
  EXPECT_EQ(terminal, 0.0);
  double default_size_max = 0.0;
  gmsh::option::getNumber("Mesh.MeshSizeMax", default_size_max);
  gmsh::option::setNumber("Mesh.MeshSizeMax", 0.125);
  gmsh::option::setNumber("General.Terminal", 1);
  gmsh::model::add("hipfai_gmsh_runtime_test");
  reset_gmsh_locked(gmsh_lock);
  double size_max = 0.0;
  gmsh::option::getNumber("Mesh.MeshSizeMax", size_max);
  EXPECT_EQ(size_max, default_size_max);
  gmsh::option::getNumber("General.Terminal", terminal);
  EXPECT_EQ(terminal, 0.0);
  std::vector<std::string> models;
  gmsh::model::list(models);
  for (const auto& name : models) EXPECT_NE(name, "hipfai_gmsh_runtime_test");
  // Still usable after the restart.
  gmsh::model::add("hipfai_gmsh_runtime_after_reset");
  gmsh::model::occ::addBox(0, 0, 0, 1, 1, 1);
  gmsh::model::occ::synchronize();
  gmsh::vectorpair volumes;
  gmsh::model::getEntities(volumes, 3);
  EXPECT_EQ(volumes.size(), 1u);
  gmsh::clear();
}

}  // namespace
}  // namespace hipfai::geometry
