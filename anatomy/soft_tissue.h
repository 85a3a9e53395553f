// hipfai — femoral and acetabular cartilage and the labrum synthesised on segmented bones (CT
// gives bone only), as closed solids a hip model can carry (geometry/hip_model.h).
//
// Method (a RIGHT hip in working coordinates; c = the femoral head's sphere centre):
//   patches   the femoral head region: the femur vertices within max(0.5 mm, 2.5 rms) of the head
//             sphere whose normals face away from c (within 40 deg), or the given vertices; the
//             lunate surface: geometry::find_lunate_surface about the head sphere (the horseshoe:
//             the fossa and the notch are not on it). Each is made a clean manifold patch: the
//             triangles with three patch corners, the largest edge-connected part, holes smaller
//             than a 3 mm disc filled (band noise; a fovea is 10 mm or more across and stays
//             bare), and the triangles at a vertex where the patch pinches (two fans) dropped
//             until none is left.
//   layers    a LAYER SOLID by radial extrusion about c: every patch vertex x is placed at r_in(x)
//             and r_out(x) along (x - c)/|x - c|; the inner surface (re-wound), the outer surface
//             and one quad per boundary edge close it. Closed and manifold by construction for a
//             manifold patch, and free of self-intersection while the patch is star-shaped from c
//             (a head region and a lunate surface are: every ray from c crosses them once).
//             Femoral cartilage: r_in = |x - c| (the bone), r_out = r_in + t_f(x); acetabular
//             cartilage: r_out = |x - c| (the bone), r_in = r_out - t_a(x). The bone side of each
//             layer is the bone's own triangles, so the bone/cartilage interface is shared exactly.
//   thickness t_f: the generator's lens (geometry/hip_generator.cpp): thickest (t_f,max) at the
//             patch point farthest from its edge, zero at the edge, along the thin-lens profile
//             t_f = t_max (cos(b_max - b) - cos b_max) / (1 - cos b_max), b the angle (seen from c)
//             to the nearest edge vertex, b_max its largest value; t_a: constant (thesis §4.3.2.2).
//   joint     along every ray from c, the gap g between the femoral and the acetabular bone (ray
//   space     casts: the femur from c, the pelvis from c) is compared with t_f + t_a there (t_a = 0
//             where the ray meets the pelvis off the lunate surface, t_f = 0 off the head region);
//             where g < t_f + t_a both are scaled by g / (t_f + t_a), so the cartilages of the
//             congruent loaded joint touch; a wider gap is left open. Both layers use the same
//             rule along the same rays, so they meet rather than overlap; the acetabular joint
//             side is then also kept on or above the femoral layer's outer surface along its own
//             ray (the two surfaces are piecewise linear over different meshes, and t_a drops to
//             zero off the lunate surface between neighbouring femoral rays).
//   minimum   no layer is thinner than min_thickness_mm (the articular sphericity tolerance, 0.1 mm:
//             surfaces that close are touching, not penetrating, for the study): it keeps the
//             femoral layer's edge and a narrow joint space from collapsing into degenerate
//             triangles. Where the gap is under two minima the cartilages overlap by at most that.
//   labrum    a triangular section (base `labrum_base_mm` wide on the rim, tip `labrum_height_mm`
//             above it, the generator's section) in the meridian plane of the acetabular axis at
//             every 2.5 deg of clock angle: the rim's polar angle (Acetabulum::rim, plane-fit
//             points only) is averaged over +-10 deg of clock (triangular weights); a section
//             needs a rim point within 10 deg on both sides (so gaps of up to 20 deg are bridged)
//             and lunate surface within 30 deg below the rim within +-5 deg of clock (the
//             horseshoe's opening, the notch, where the rim finder may still keep the rim, is
//             left open); its base lies on the
//             ray at the rim's polar angle, from the articular sphere (lunate radius - t_a) out;
//             its inner face follows the articular sphere, or the femoral cartilage's outer
//             surface where that stands higher (the labrum seals on the head). The section is
//             tilted towards the opening in 0.5 deg steps (up to 10 deg) until it is clear of the
//             pelvis; a section that still is not, or that meets the femur (the neck passing
//             under the rim), is left out. One swept solid per run of kept sections, each with end
//             caps (open at the notch when the bones show one; the transverse ligament is not
//             modelled); a rim kept all round over a lunate surface without an opening (a
//             segmentation that fills the fossa and notch, as LHDL's does) gives a closed ring.
//
// Why not offset surfaces or Booleans: an offset of a real bone's noisy surface self-intersects
// and needs a repair step; a Boolean of spheres (the generator's) does not follow the bone. The
// radial layer follows the bone exactly and is valid by construction.
#pragma once

#include "anatomy/acetabulum.h"
#include "core/literature.h"
#include "geometry/tri_mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hipfai::anatomy {

struct SoftTissueOptions {
  double femoral_max_thickness_mm = literature::kFemoralCartilageMaxThicknessMm;
  double acetabular_thickness_mm = literature::kAcetabularCartilageThicknessMm;
  double labrum_height_mm = literature::kLabrumHeightMm;
  double labrum_base_mm = literature::kLabrumBaseWidthMm;
  // Thinnest layer kept (see the header comment).
  double min_thickness_mm = literature::kSphericityToleranceMm;
  double labrum_step_deg = 2.5;  // clock angle between labrum sections
};

struct SoftTissueRequest {
  const geometry::TriMesh* femur = nullptr;   // required: closed, outward, in working coordinates
  const geometry::TriMesh* pelvis = nullptr;  // required: same coordinates, the pose of the joint
  geometry::Vec3 head_centre_mm = geometry::Vec3::Zero();  // femoral head sphere (in `femur`'s pose)
  double head_radius_mm = 0.0;
  double head_fit_rms_mm = 0.0;               // its fit's RMS: sets the head band (see the method)
  // Femur vertex indices of the articular head; empty: found on the sphere (see the method).
  std::vector<std::int32_t> head_vertices;
  const Acetabulum* acetabulum = nullptr;     // required: lunate sphere, opening axis, rim
  SoftTissueOptions options;
  std::string femur_name = "femur", pelvis_name = "pelvis";  // for messages
};

// One cartilage layer's numbers.
struct LayerReport {
  double covered_area_mm2 = 0.0;     // area of its bone side (the patch)
  double mean_thickness_mm = 0.0;    // area-weighted over the patch
  double min_thickness_mm = 0.0;
  double max_thickness_mm = 0.0;
  double volume_mm3 = 0.0;
  std::size_t patch_vertices = 0;
  // Patch area (mm^2) where the bone-to-bone gap was narrower than t_f + t_a (the layer scaled
  // down), and where it was under twice the minimum thickness (the cartilages overlap there).
  double narrowed_area_mm2 = 0.0;
  double overlap_area_mm2 = 0.0;
  std::size_t holes_filled = 0;      // small holes of the patch filled
  std::size_t pinches_removed = 0;   // triangles dropped at pinched vertices
};

struct SoftTissueReport {
  LayerReport femoral, acetabular;
  double labrum_volume_mm3 = 0.0;
  int labrum_sections = 0;           // kept
  int labrum_sections_total = 0;     // tried (360 / labrum_step_deg)
  int labrum_pieces = 0;             // swept solids (runs of kept sections)
  int labrum_dropped_pelvis = 0;     // sections not cleared of the pelvis
  int labrum_dropped_femur = 0;      // sections meeting the femur (the neck under the rim)
  int labrum_missing_rim = 0;        // sections where the rim is missing (the notch)
  bool labrum_closed_ring = false;
  double seconds = 0.0;
};

// Closed, manifold, outward solids; each cartilage carries the vertex field "thickness_mm" (the
// layer's thickness along the ray of that vertex, on both of its surfaces).
struct SoftTissues {
  geometry::TriMesh femoral_cartilage, acetabular_cartilage, labrum;
  SoftTissueReport report;
};

// Throws hipfai::Error with one line for missing or empty bones, no head region ("<femur>: no
// femoral head region on the sphere ..."), no lunate surface, or no rim to carry a labrum.
SoftTissues synthesise_soft_tissues(const SoftTissueRequest& request);

}  // namespace hipfai::anatomy
