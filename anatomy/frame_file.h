// hipfai — reading the anatomical frames a user gives (a JSON file), for `hipfai assess` on bones
// that are not whole enough for the frames to be found on them.
//
// Three shapes are accepted (coordinates of the input meshes, mm; unknown keys are ignored):
//
// (a) axes, the shape of the assessment's own output ("source_kind" "axes"):
//       { "side": "right" | "left",                      optional
//         "hjc_mm": [x, y, z],                            optional
//         "frames": { "pelvis": {"origin_mm": [..], "right": [..], "anterior": [..], "superior": [..]},
//                     "femur":  { the same } } }          either frame may be missing, not both
//     Directions are normalised (any length but zero); the three axes must be orthogonal within
//     kFrameOrthogonalityTolerance and right-handed (right x anterior = superior).
//
// (b) landmarks ("landmarks"):
//       { "side": ..,                                    required with femur landmarks
//         "hjc_mm": [..],                                 optional
//         "pelvis_landmarks": {"asis_right_mm", "asis_left_mm", "pubic_tubercle_right_mm",
//                              "pubic_tubercle_left_mm"},
//         "femur_landmarks": {"head_centre_mm", "medial_epicondyle_mm", "lateral_epicondyle_mm"} }
//     either group may be missing, not both; the frames are built by anterior_pelvic_plane_frame
//     and femur_epicondylar_frame below. hjc_mm defaults to the femoral head centre.
//
// (c) a hipfai hip model.json as `hipfai generate` writes it ("hip-model"; geometry/hip_model.h):
//     "format": "hipfai-hip-model", "handedness" ("right"; absent means right), "hjc_mm",
//     "lateral", "superior", "flexion_axis", "adduction_axis", "internal_rotation_axis",
//     "neck_axis". The model is a right hip in its hip frame (geometry/hip_frame.h), so the pelvis
//     and femur frames are both that frame: origin hjc_mm, right = lateral, superior, anterior =
//     superior x lateral; the motion axes must be those same axes (flexion about right, adduction
//     about anterior, internal rotation about superior) within the tolerance. Also the neck axis.
//     A left model is refused: hipfai's hip models are right hips (a left hip is mirrored,
//     anatomy/side.h).
#pragma once

#include "anatomy/anatomical_frame.h"
#include "anatomy/side.h"

#include <Eigen/Geometry>

#include <filesystem>
#include <optional>
#include <string>

namespace hipfai::anatomy {

// Largest |cosine| between two axes of a frame that still counts as orthogonal (0.057 deg off).
// Frames written with double precision by a program meet it by many orders of magnitude; frames
// typed by hand with 3-4 significant digits meet it too; a frame whose axes were not
// orthogonalised (e.g. superior taken as the raw shaft direction) does not.
inline constexpr double kFrameOrthogonalityTolerance = 1e-3;

// Landmarks closer than this cannot define a direction: picking a bony landmark on a CT or MRI
// segmentation is uncertain to about a voxel (0.5-1 mm), so two landmarks 1 mm apart give an axis
// uncertain by tens of degrees.
inline constexpr double kMinLandmarkSeparationMm = 1.0;

// What a frame file gives; source_kind says which shape it had.
struct UserFrame {
  std::optional<Side> side;              // "side" (or the model's handedness)
  std::optional<geometry::Vec3> hjc_mm;  // hip joint centre, mm
  std::optional<AnatomicalFrame> pelvis;
  std::optional<AnatomicalFrame> femur;
  std::optional<geometry::Vec3> neck_axis;  // unit, from the HJC towards the neck (hip models only)
  std::string source_kind;               // "axes", "landmarks" or "hip-model"
};

// The anterior pelvic plane (Lewinnek et al. 1978, J Bone Joint Surg Am 60:217) landmarks.
struct AppLandmarks {
  geometry::Vec3 asis_right_mm = geometry::Vec3::Zero();  // right anterior superior iliac spine
  geometry::Vec3 asis_left_mm = geometry::Vec3::Zero();   // left anterior superior iliac spine
  geometry::Vec3 pubic_tubercle_right_mm = geometry::Vec3::Zero();
  geometry::Vec3 pubic_tubercle_left_mm = geometry::Vec3::Zero();
};

// The femoral landmarks of the ISB femur frame (Wu et al. 2002, J Biomech 35:543).
struct EpicondylarLandmarks {
  geometry::Vec3 head_centre_mm = geometry::Vec3::Zero();
  geometry::Vec3 medial_epicondyle_mm = geometry::Vec3::Zero();
  geometry::Vec3 lateral_epicondyle_mm = geometry::Vec3::Zero();
};

// The anterior pelvic plane frame: the plane through both ASIS and the pubic tubercles' midpoint;
// right from the left ASIS to the right one; superior in the plane, perpendicular to right,
// towards the ASIS from the pubic midpoint; anterior = superior x right, the plane's normal (it
// points anteriorly because the landmarks are labelled, and (right, anterior, superior) is then
// right-handed). Origin `origin_mm`. Throws hipfai::Error ("<what>: ...") when the ASIS are
// closer than kMinLandmarkSeparationMm, or the pubic midpoint is that close to their line.
AnatomicalFrame anterior_pelvic_plane_frame(const AppLandmarks& landmarks, const geometry::Vec3& origin_mm,
                                            const std::string& what);

// The femur frame of Wu et al. (2002) from the head centre and the epicondyles: origin the head
// centre, superior from the epicondyles' midpoint to the head centre, right perpendicular to it in
// the plane of superior and the epicondyle line, towards the subject's right (the lateral
// epicondyle for a right femur, the medial one for a left), anterior = superior x right. Throws
// hipfai::Error when two landmarks are closer than kMinLandmarkSeparationMm or the epicondyle line
// is within that distance of parallel to superior.
AnatomicalFrame femur_epicondylar_frame(const EpicondylarLandmarks& landmarks, Side side, const std::string& what);

// Reads `path` (parse_frame_file with the path as the name); hipfai::Error when it cannot be opened.
UserFrame read_frame_file(const std::filesystem::path& path);

// The frame file's content as it reads on bones moved by `isometry`. An improper one (a mirror)
// makes a right hip a left one: the subject's right becomes the mirror image of the old left, and
// a given side flips.
UserFrame transformed(const UserFrame& frame, const Eigen::Affine3d& isometry);

// Parses a frame file's text. Throws hipfai::Error "<name>: <key>: <problem>" (one line) for
// invalid JSON, an unrecognised shape, a missing or malformed key (a vector must be 3 finite
// numbers; a direction also non-zero), axes not orthogonal or left-handed, coincident landmarks,
// or a hip model whose axes disagree.
UserFrame parse_frame_file(const std::string& text, const std::string& name);

}  // namespace hipfai::anatomy
