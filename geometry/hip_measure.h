// hipfai — the clinical angles measured back from meshes (never from generator parameters).
//
// Both measurements work on triangle surfaces and the hip frame only, so they apply to generated
// hips (where they check the generator) and to users' segmented hips alike.
//
// CE angle (Wiberg): the acetabular bone and cartilage are cut by the frontal plane through the
// HJC (normal = superior x lateral, i.e. anterior). Among the section points superior of the HJC
// (within 2.5 x the nearest section distance, so a large pelvis block does not matter), the most
// lateral-superior rim point is the one with the largest angle from `superior` towards `lateral`;
// CE is that angle. The labrum is deliberately not an input: the bony rim defines CE.
//
// Alpha angle (Nötzli): the head sphere is fitted (linear least squares) to the outermost
// bone+cartilage vertices within 60 deg of the pole (-neck axis). In a half-plane containing the
// neck axis through the fitted centre, the section contour of bone and cartilage is sampled, and
// walking from the pole towards the neck, the first angle (from the neck axis) where the
// outermost contour deviates from the sphere by more than `tolerance_mm` is that plane's alpha.
// THE alpha angle is the one in Nötzli's plane: the oblique axial plane through the neck axis,
// i.e. the half-plane towards anterior ("3 o'clock", Nötzli et al. 2002). Besides it: the clock
// profile (every profile_step_deg around the neck) and the largest alpha over the
// anterosuperior sector (2 deg steps, then 0.25 deg around the best), with its clock position.
//
// Clock positions are angles about the neck axis from anterior (3 o'clock) towards superior
// (12 o'clock): 0 = 3:00, 45 = 1:30, 90 = 12:00, -90 = 6:00 (a right hip seen from lateral).
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <utility>
#include <vector>

namespace hipfai::geometry {

struct PlaneSegment {
  Vec3 a;
  Vec3 b;
};

// Intersection of a mesh with the plane through `point` with normal `normal` (unit), as segments.
std::vector<PlaneSegment> plane_section(const TriMesh& mesh, const Vec3& point, const Vec3& normal);

enum class MeasureStatus { kOk, kNoSection };

struct CeMeasurement {
  MeasureStatus status = MeasureStatus::kNoSection;
  double ce_deg = 0.0;
  Vec3 rim_point_mm = Vec3::Zero();  // the lateral rim point used
};

CeMeasurement measure_ce_angle(const std::vector<const TriMesh*>& acetabulum, const Vec3& hjc_mm,
                               const Vec3& lateral, const Vec3& superior);

struct AlphaOptions {
  // Deviation from the fitted sphere that counts as leaving it. 0 = automatic: the larger of
  // 0.1 mm and 1.2 L^2 / (6 R), L the longest edge with both ends on the fitted sphere (a flat
  // triangle of that size sits up to ~L^2 / (6 R) under the sphere, so a tessellated sphere is not
  // mistaken for a departure).
  double tolerance_mm = 0.0;
  double sector_begin_deg = 0.0;  // from anterior ...
  double sector_end_deg = 90.0;   // ... to superior
  double notzli_clock_deg = 0.0;  // Nötzli's plane: anterior (3 o'clock)
  double profile_step_deg = 15.0; // clock profile step (0: no profile)
  // The head sphere, when known (e.g. fitted to the head region of a real bone); radius 0: fitted
  // here to the outermost vertices near the pole.
  Vec3 head_centre_mm = Vec3::Zero();
  double head_radius_mm = 0.0;
  // 0: walk from the pole (generated hips). > 0 (real bones): walk from the neck-side end of the
  // longest run of the contour on the sphere, bridging gaps up to this (see alpha_in_plane).
  double articular_gap_deg = 0.0;
};

// "3:00" for 0 deg, "1:30" for 45, "12:00" for 90, "4:30" for -45.
std::string clock_label(double clock_deg);

struct AlphaMeasurement {
  MeasureStatus status = MeasureStatus::kNoSection;
  double alpha_deg = 0.0;          // in Nötzli's plane (options.notzli_clock_deg)
  double plane_deg = 0.0;          // that plane's clock angle
  double max_alpha_deg = 0.0;      // largest over the anterosuperior sector ...
  double max_plane_deg = 0.0;      // ... and where (clock angle)
  std::vector<std::pair<double, double>> profile;  // (clock angle, alpha; NaN: no contour)
  std::vector<Vec3> profile_directions;            // each profile plane's unit direction (as plane_direction)
  Vec3 head_centre_mm = Vec3::Zero();
  double head_radius_mm = 0.0;
  Vec3 departure_point_mm = Vec3::Zero();
  Vec3 plane_direction = Vec3::Zero();  // unit, perpendicular to the neck axis, in Nötzli's plane
  double tolerance_mm = 0.0;
};

// `neck_axis` points from the HJC towards the neck; `superior` gives the sector's orientation
// (anterior = neck_axis x superior for a right hip, flipped to the +superior x lateral side).
AlphaMeasurement measure_alpha_angle(const std::vector<const TriMesh*>& femur, const Vec3& hjc_mm,
                                     const Vec3& neck_axis, const Vec3& superior,
                                     const Vec3& anterior, const AlphaOptions& options = {});

// Alpha of one plane (direction `u` perpendicular to the neck axis); NaN when no contour.
// articular_gap_deg as AlphaOptions::articular_gap_deg.
double alpha_in_plane(const std::vector<const TriMesh*>& femur, const Vec3& centre, double radius_mm,
                      const Vec3& neck_axis, const Vec3& u, double tolerance_mm,
                      Vec3* departure_point = nullptr, double articular_gap_deg = 0.0);

}  // namespace hipfai::geometry
