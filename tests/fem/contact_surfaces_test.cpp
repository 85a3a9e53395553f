// fem::ContactSurfaces: faces made once and turned with their body equal faces made afresh from
// the mapping in the new placement; a face the mapping does not turn with its body (a manifold
// centred elsewhere than the rotation) is made anew.
#include "fem/contact_surfaces.h"

#include "fem/contact_problem.h"
#include "fem/motion_solver.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>

#include <gtest/gtest.h>

#include <cmath>

namespace hipfai::fem {
namespace {

constexpr dealii::types::boundary_id kInner = 0, kOuter = 1;

// A shell of six cells (radii 23-25 mm about `centre`, spherical manifold there), bonded to bone 0.
struct Shell {
  dealii::Point<3> centre{1.0, -2.0, 3.0};
  ContactModel model;
  std::unique_ptr<ElasticSystem> system;

  Shell() {
    ensure_mpi_initialized();
    system = std::make_unique<ElasticSystem>(MPI_COMM_WORLD, 2, 2);
    auto& tria = system->triangulation();
    dealii::GridGenerator::hyper_shell(tria, centre, 23.0, 25.0, 6, true);  // inner id 0, outer 1
    tria.set_all_manifold_ids(0);
    tria.set_manifold(0, dealii::SphericalManifold<3>(centre));
    model.bodies = {{"cartilage", 0, {12.0, 0.45}, 0}};
    model.rigid_bodies = {{"bone", nullptr, {}, false, {}, {}, dealii::unit_symmetric_tensor<3>(), centre}};
    model.contact_pairs = {{kOuter, -1, kInner}};
    place();
  }
  void place() {
    system->place_bodies(model);
    system->setup(model);
  }
};

dealii::Tensor<2, 3> rotation_about(const dealii::Tensor<1, 3>& axis, double degrees) {
  return rotation_about_axis(axis, degrees * M_PI / 180.0);
}

// Every face of the boundaries equals the face made from the mapping now, inside the face and
// on its extension (the segments use both).
void expect_faces_as_made_now(const Shell& shell, const ContactSurfaces& surfaces, double tolerance) {
  for (const auto id : {kInner, kOuter}) {
    const std::vector<FacePatch>& faces = surfaces.faces(id);
    ASSERT_FALSE(faces.empty());
    for (const FacePatch& face : faces) {
      const FacePatch fresh(shell.system->mapping(), face.cell, face.face_no);
      for (const double s : {-0.3, 0.0, 0.37, 1.0, 1.2}) {
        for (const double t : {-0.2, 0.5, 1.0, 1.3}) {
          dealii::Point<3> x, y;
          dealii::Tensor<1, 3> xs, xt, ys, yt;
          face.evaluate(s, t, x, xs, xt);
          fresh.evaluate(s, t, y, ys, yt);
          EXPECT_LT(x.distance(y), tolerance);
          EXPECT_LT((xs - ys).norm() + (xt - yt).norm(), tolerance);
          EXPECT_LT((face.normal(s, t) - fresh.normal(s, t)).norm(), 1e-12);
        }
      }
      for (unsigned int d = 0; d < 3; ++d) {
        EXPECT_NEAR(face.box_min[d], fresh.box_min[d], tolerance);
        EXPECT_NEAR(face.box_max[d], fresh.box_max[d], tolerance);
      }
    }
  }
}

TEST(ContactSurfaces, TurnedFacesEqualFacesMadeInTheNewPlacement) {
  Shell shell;
  ContactSurfaces surfaces;
  surfaces.update(*shell.system, shell.model);
  const std::size_t n_faces = surfaces.faces(kInner).size() + surfaces.faces(kOuter).size();
  EXPECT_EQ(surfaces.faces_made(), n_faces);
  expect_faces_as_made_now(shell, surfaces, 1e-12);

  // Two placements turned about the manifold's centre: no face made again.
  for (const double degrees : {7.0, -23.0}) {
    shell.model.rigid_bodies[0].rotation = rotation_about(dealii::Tensor<1, 3>({0.3, -1.0, 0.4}), degrees);
    shell.place();
    surfaces.update(*shell.system, shell.model);
    EXPECT_EQ(surfaces.faces_made(), n_faces);
    expect_faces_as_made_now(shell, surfaces, 1e-11);
  }
}

TEST(ContactSurfaces, FacesTheMappingDoesNotTurnAreMadeAnew) {
  Shell shell;
  ContactSurfaces surfaces;
  surfaces.update(*shell.system, shell.model);
  const std::size_t n_faces = surfaces.faces_made();
  // Turned about a point 5 mm from the manifold's centre: the vertices turn, the spherical
  // manifold does not, so the curved faces are other faces than the turned ones.
  shell.model.rigid_bodies[0].rotation = rotation_about(dealii::Tensor<1, 3>({0.0, 0.0, 1.0}), 12.0);
  shell.model.rigid_bodies[0].rotation_center_mm = shell.centre + dealii::Tensor<1, 3>({5.0, 0.0, 0.0});
  shell.place();
  surfaces.update(*shell.system, shell.model);
  EXPECT_EQ(surfaces.faces_made(), 2 * n_faces);
  expect_faces_as_made_now(shell, surfaces, 1e-12);
}

// A face of a degree-2 mapping is interpolated at degree 2 (9 points): it is the mapping itself,
// inside the face and on its polynomial extension, to round-off.
TEST(ContactSurfaces, APatchIsItsMappingInsideAndOutsideTheFace) {
  Shell shell;
  ContactSurfaces surfaces;
  surfaces.update(*shell.system, shell.model);
  for (const FacePatch& face : surfaces.faces(kOuter)) {
    ASSERT_EQ(face.degree(), 2u);
    for (const double s : {-0.4, 0.13, 0.5, 0.91, 1.35}) {
      for (const double t : {-0.25, 0.0, 0.77, 1.4}) {
        dealii::Point<3> x;
        dealii::Tensor<1, 3> xs, xt;
        face.evaluate(s, t, x, xs, xt);
        const dealii::Point<3> mapped =
            shell.system->mapping().transform_unit_to_real_cell(face.cell, face.unit_cell_point(s, t));
        EXPECT_LT(x.distance(mapped), 1e-12);
      }
    }
  }
}

TEST(ContactSurfaces, AFixedBodyKeepsItsFaces) {
  Shell shell;
  shell.model.bodies[0].bonded_rigid_body = -1;
  shell.place();
  ContactSurfaces surfaces;
  surfaces.update(*shell.system, shell.model);
  const FacePatch first = surfaces.faces(kOuter).front();
  surfaces.update(*shell.system, shell.model);
  EXPECT_EQ(surfaces.faces_made(), surfaces.faces(kInner).size() + surfaces.faces(kOuter).size());
  EXPECT_EQ(surfaces.faces(kOuter).front().samples(), first.samples());
}

// The search ahead (fem/contact_search_ahead.h) searches a placement the mesh is not in yet: its
// faces and search radius must be those the mesh gives once placed, bit for bit.
TEST(ContactSurfaces, PredictedFacesAndDiameterAreThoseOfThePlacementBitForBit) {
  Shell shell;
  ContactSurfaces surfaces;
  surfaces.update(*shell.system, shell.model);
  ContactModel next = shell.model;
  next.rigid_bodies[0].rotation = rotation_about(dealii::Tensor<1, 3>({0.4, -1.0, 0.3}), 17.0);
  const ContactSurfaces predicted = surfaces.predicted(next);
  const double diameter = shell.system->diameter_if_placed(next);
  EXPECT_FALSE(surfaces.same_faces(predicted));  // the faces have not turned yet
  shell.model = next;
  shell.place();
  surfaces.update(*shell.system, shell.model);
  EXPECT_TRUE(surfaces.same_faces(predicted));
  EXPECT_EQ(shell.system->diameter(), diameter);
  EXPECT_EQ(diameter, dealii::GridTools::diameter(shell.system->triangulation()));

  // About a point that is not the manifold's centre the mapping does not turn with the body:
  // update() makes the faces anew, and they are not the predicted (turned) ones.
  next.rigid_bodies[0].rotation_center_mm = shell.centre + dealii::Tensor<1, 3>({0.0, 3.0, 0.0});
  next.rigid_bodies[0].rotation = rotation_about(dealii::Tensor<1, 3>({1.0, 0.0, 0.0}), 9.0);
  const ContactSurfaces elsewhere = surfaces.predicted(next);
  shell.model = next;
  shell.place();
  surfaces.update(*shell.system, shell.model);
  EXPECT_FALSE(surfaces.same_faces(elsewhere));
}

}  // namespace
}  // namespace hipfai::fem
