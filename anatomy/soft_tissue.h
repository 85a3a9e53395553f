// hipfai — femoral and acetabular cartilage and the labrum synthesised on segmented bones (CT
// gives bone only), as closed solids a hip model can carry (geometry/hip_model.h).
//
// Method (a RIGHT hip in working coordinates; c = the joint centre: the HJC given, else the femoral
// head's sphere centre, which also selects the head region):
//   patches   the femoral head region: the femur vertices within max(0.5 mm, 2.5 rms) of the head
//             sphere whose normals face away from its centre (within 40 deg) and that lie beyond the
//             head-neck junction (the alpha angle's clock profile, Nötzli's definition of where the
//             head leaves its sphere, when given), or the given vertices; the
//             lunate surface: geometry::find_lunate_surface about the head sphere, which on a
//             real bone may still reach over the fossa floor (see "fossa" below). Each is made a
//             clean manifold patch: the
//             triangles with three patch corners, the largest edge-connected part, holes filled
//             (those smaller than a 3 mm disc: band noise; on the head also every hole whose bone
//             lies below the sphere's band: dips that cartilage fills in vivo, and the fovea,
//             which faces the acetabular fossa where nothing articulates, so covering it changes
//             no contact; a layer with holes meshes into distorted hexahedra at the FE's sizes;
//             bone standing out of the sphere, a cam or an osteophyte, stays bare), and the
//             triangles at a vertex where the patch pinches (two fans) dropped until none is left.
//   layers    a LAYER SOLID by radial extrusion about c: every patch vertex x is placed at r_in(x)
//             and r_out(x) along (x - c)/|x - c|; the inner surface (re-wound), the outer surface
//             and one quad per boundary edge close it. Closed and manifold by construction for a
//             manifold patch, and free of self-intersection while the patch is star-shaped from c
//             (a head region and a lunate surface are: every ray from c crosses them once).
//             Femoral cartilage: r_in = |x - c| (the bone), r_out = r_in + t_f(x); acetabular
//             cartilage: r_out = |x - c| (the bone), r_in = r_out - t_a(x). The bone side of each
//             layer is the bone's own triangles, so the bone/cartilage interface is shared exactly.
//   joint     the thesis' model (§4.3.2.2): the two articular surfaces are portions of ONE sphere
//   space     (they deviate from sphericity by < 0.1 mm: Macirowski, Tepic & Mann 1994), here
//             about c, so the joint stays congruent as the femur turns about c. Its radius r_art
//             splits the bone-to-bone gap g (ray casts from c) where the femoral cartilage is
//             thickest: over the femoral rays that meet the lunate surface with a lens (below)
//             within 10 % of t_f,max, the median of the meeting point r_f + g t_f,max /
//             (t_f,max + t_a) when g < t_f,max + t_a (the literature ratio), else r_p - t_a (the
//             acetabular cartilage keeps its constant thickness, the femoral takes the rest);
//             at most r_min + t_f,max, r_min the deepest head bone whose ray meets the lunate
//             surface, outside the head's filled holes (the fovea, bare of cartilage: the
//             ligamentum teres inserts there), so that the femoral cartilage is nowhere thicker
//             than its literature maximum. The median alone is biased up by the spread of the
//             split points about the thickest spot (on the generated hips 25.04-25.09 mm against
//             the generator's 25.0; with the bound 25.00).
//   fossa     the acetabular fossa taken off the lunate patch once r_art is known (r_art itself is
//             measured on the whole patch: its rays face the dome, where the head's cartilage is
//             thickest): every patch triangle with a corner whose bone lies deeper from c than
//             r_art + fossa_depth_mm (the thickest cartilage the thesis' model holds, both layers'
//             literature thicknesses: literature::kAcetabularCartilageMaxThicknessMm) goes, so the
//             acetabular layer is nowhere thicker than that. The fossa opens inferiorly into the
//             acetabular notch: a removed part the patch encloses (a hole) is opened to the
//             patch's outline along the inferior direction, taking the patch triangles inferior of
//             the part's centre within its own width (seen from c, across the inferior meridian
//             through its centre), so the layer is one C-shaped piece with one outline, as the
//             generator's horseshoe; the largest piece is kept. On the generated bones, which have
//             no fossa (their socket's bone is the articular sphere plus the acetabular thickness),
//             it takes nothing.
//   thickness acetabular: from the lunate bone to the sphere, t_a(y) = |y - c| - r_art. Femoral:
//             from the head to the sphere over the whole head region, t_f(x) = r_art - |x - c|,
//             also where the ray meets no lunate surface in this pose (facing the fossa, beyond
//             the rim): the head turns under the socket (in flexion its anterior part, beside a
//             cam, comes under the loaded dome), and a congruent joint stays congruent only if
//             all of its head is on the sphere, as the generator's is (its lens lies between an
//             eccentric head ball and the R sphere: it thins to its edge because the bone rises
//             to the sphere there, not because its surface drops below it). The cartilage thus
//             evens out the bone's own departures from the sphere. The lens (t_f,max at the
//             patch point farthest from its edge, zero at the edge, t_max (cos(b_max - b) -
//             cos b_max) / (1 - cos b_max), b the angle seen from c to the nearest edge vertex,
//             b_max its largest value) only selects where r_art is measured. The acetabular joint
//             side is also kept on or above the femoral layer's outer surface along its own ray
//             (both are piecewise linear over different meshes).
//   minimum   no layer is thinner than min_thickness_mm (the articular sphericity tolerance, 0.1 mm:
//             surfaces that close are touching, not penetrating, for the study): where a bone
//             stands within it of the sphere (a bump), its layer stands proud of the sphere by up to
//             that much, plus what the bone itself stands out (LayerReport::overlap_area_mm2 says
//             where). Except at the head region's edge: there such bone is left bare (the region
//             peeled from its edge inwards over the triangles with a vertex within the minimum
//             of the sphere, until no edge vertex is), as on the generated heads, whose bone
//             between their lens' edge and the head-neck junction is the articular sphere
//             itself; a ridge standing proud along the edge concentrated the femoral
//             cartilage's stress there.
//   labrum    a triangular section (base `labrum_base_mm` wide on the rim, tip `labrum_height_mm`
//             above it, the generator's section) in the meridian plane of the acetabular axis through c at
//             every 2.5 deg of clock angle: the rim's polar angle (Acetabulum::rim, plane-fit
//             points only) is averaged over +-10 deg of clock (triangular weights); a section
//             needs a rim point within 10 deg on both sides (so gaps of up to 20 deg are bridged)
//             and lunate surface within 30 deg below the rim within +-5 deg of clock (the
//             horseshoe's opening, the notch, where the rim finder may still keep the rim, is
//             left open); its base lies on the
//             ray at the rim's polar angle, from the common articular sphere out;
//             its inner face follows the articular sphere, or the femoral cartilage's outer
//             surface where that stands higher (the labrum seals on the head). The section is
//             tilted towards the opening in 0.5 deg steps (up to 10 deg) until it is clear of the
//             pelvis (clear: no probe more than min_thickness_mm inside the pelvis or its
//             cartilage, the probes moved that far towards the acetabular axis; the base lies on
//             the rim's face, whose triangles bulge into a socket shallower than a hemisphere by
//             a chord's sagitta, 0.02 mm at 2 mm edges, which read as inside would tilt every
//             section a step deeper than the rim); a section that still is not, or that meets the
//             femur (the neck passing under the rim), is left out. One swept solid per run of kept sections, each with end
//             caps (open at the notch when the bones show one; the transverse ligament is not
//             modelled); a rim kept all round over a lunate surface without an opening (a
//             segmentation that fills the fossa and notch with bone within the fossa rule's depth)
//             gives a closed ring; a fossa opened to the notch (LHDL's) leaves the labrum open there.
//
// Why not offset surfaces or Booleans: an offset of a real bone's noisy surface self-intersects
// and needs a repair step; a Boolean of spheres (the generator's) does not follow the bone. The
// radial layer follows the bone exactly and is valid by construction.
#pragma once

#include "anatomy/acetabulum.h"
#include "core/literature.h"
#include "geometry/tri_mesh.h"

#include <cstdint>
#include <optional>
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
  // Bone of the lunate patch deeper than the articular sphere by more than this is the fossa and
  // bears no cartilage (see "fossa" in the header comment).
  double fossa_depth_mm = literature::kAcetabularCartilageMaxThicknessMm;
  double labrum_step_deg = 2.5;  // clock angle between labrum sections
};

struct SoftTissueRequest {
  const geometry::TriMesh* femur = nullptr;   // required: closed, outward, in working coordinates
  const geometry::TriMesh* pelvis = nullptr;  // required: same coordinates, the pose of the joint
  geometry::Vec3 head_centre_mm = geometry::Vec3::Zero();  // femoral head sphere (in `femur`'s pose)
  // The joint centre the layers are extruded from and the labrum's sections are laid about (the
  // HJC of the hip frame); unset: the head sphere's centre.
  std::optional<geometry::Vec3> joint_centre_mm;
  double head_radius_mm = 0.0;
  double head_fit_rms_mm = 0.0;               // its fit's RMS: sets the head band (see the method)
  // Femur vertex indices of the articular head; empty: found on the sphere (see the method).
  std::vector<std::int32_t> head_vertices;
  // Where the head ends towards the neck (used when head_vertices is empty): the alpha angle's
  // clock profile, as (unit direction perpendicular to neck_axis, alpha in deg) in `femur`'s pose;
  // head-region vertices closer to the neck axis than alpha at their clock are left out.
  // Empty: no such limit.
  geometry::Vec3 neck_axis = geometry::Vec3::Zero();
  std::vector<std::pair<geometry::Vec3, double>> head_neck_junction;
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
  // Patch area (mm^2) whose articular side lies on the common articular sphere, and where the
  // bone stands within the minimum thickness of it (the layer kept at the minimum stands proud of
  // the sphere there by up to that much).
  double articular_area_mm2 = 0.0;
  double overlap_area_mm2 = 0.0;
  std::size_t holes_filled = 0;      // holes of the patch filled (see "patches" above)
  std::size_t pinches_removed = 0;   // triangles dropped at pinched vertices
};

struct SoftTissueReport {
  LayerReport femoral, acetabular;
  double articular_radius_mm = 0.0;  // the common articular sphere about the joint centre
  std::size_t femoral_rim_peeled = 0;  // head-region triangles left bare at its edge ("minimum" above)
  // The fossa taken off the lunate patch ("fossa" above): its area deeper than the rule, the area
  // of the patch taken with it to open it towards the notch, and the number of enclosed parts so
  // opened.
  double fossa_area_mm2 = 0.0;
  double fossa_opening_area_mm2 = 0.0;
  int fossa_holes_opened = 0;
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
// femoral head region on the sphere ..."), no lunate surface, none left outside the fossa, a head
// region facing no lunate surface, no rim to carry a labrum, or a fossa_depth_mm not above
// min_thickness_mm.
SoftTissues synthesise_soft_tissues(const SoftTissueRequest& request);

}  // namespace hipfai::anatomy
