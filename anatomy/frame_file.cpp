// hipfai — reading the anatomical frames a user gives: JSON (nlohmann_json) in one of three
// shapes (axes, landmarks, a hip model.json), each checked and turned into AnatomicalFrames.
#include "anatomy/frame_file.h"

#include "core/error.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace hipfai::anatomy {

namespace {

using geometry::Vec3;
using Json = nlohmann::json;

// A vector [x, y, z] of finite numbers at json[key]; `where` names json in messages.
Vec3 read_point(const Json& json, const std::string& key, const std::string& where) {
  if (!json.contains(key)) throw_error(where, key, ": missing");
  const Json& value = json[key];
  if (!value.is_array() || value.size() != 3) throw_error(where, key, ": expected [x, y, z]");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const Json& component = value[static_cast<std::size_t>(i)];
    if (!component.is_number()) throw_error(where, key, ": expected [x, y, z] of numbers");
    v[i] = component.get<double>();
    if (!std::isfinite(v[i])) throw_error(where, key, ": expected finite numbers");
  }
  return v;
}

// A direction: a non-zero vector, normalised.
Vec3 read_direction(const Json& json, const std::string& key, const std::string& where) {
  const Vec3 v = read_point(json, key, where);
  const double length = v.norm();
  // The smallest length whose normalisation is still accurate to double precision; a typed zero
  // vector (or one of subnormals) is refused.
  if (!(length > 1e-150) || !std::isfinite(length)) throw_error(where, key, ": is zero, not a direction");
  return v / length;
}

// Checks an AnatomicalFrame's axes: orthogonal within the tolerance and right-handed.
void check_frame(const AnatomicalFrame& frame, const std::string& what) {
  const struct {
    const char* a;
    const char* b;
    double cosine;
  } pairs[] = {{"right", "anterior", frame.right.dot(frame.anterior)},
               {"right", "superior", frame.right.dot(frame.superior)},
               {"anterior", "superior", frame.anterior.dot(frame.superior)}};
  for (const auto& pair : pairs) {
    if (!(std::abs(pair.cosine) <= kFrameOrthogonalityTolerance)) {
      throw_error(what, ": ", pair.a, " and ", pair.b, " are not orthogonal (cosine ", pair.cosine, ", at most ",
                  kFrameOrthogonalityTolerance, ")");
    }
  }
  if (!(frame.right.cross(frame.anterior).dot(frame.superior) > 0.0)) {
    throw_error(what, ": the axes are left-handed (right x anterior must be superior)");
  }
}

std::optional<Side> read_side(const Json& json, const std::string& name) {
  if (!json.contains("side")) return std::nullopt;
  if (!json["side"].is_string()) throw_error(name, ": side: expected \"right\" or \"left\"");
  const std::string text = json["side"].get<std::string>();
  if (text != "right" && text != "left") throw_error(name, ": side: '", text, "' is not \"right\" or \"left\"");
  return side_from_name(text);
}

const Json& read_object(const Json& json, const std::string& key, const std::string& where) {
  if (!json.contains(key) || !json[key].is_object()) throw_error(where, key, ": expected an object");
  return json[key];
}

UserFrame parse_axes(const Json& json, const std::string& name) {
  UserFrame user;
  user.source_kind = "axes";
  user.side = read_side(json, name);
  if (json.contains("hjc_mm")) user.hjc_mm = read_point(json, "hjc_mm", name + ": ");
  const Json& frames = read_object(json, "frames", name + ": ");
  for (const char* bone : {"pelvis", "femur"}) {
    if (!frames.contains(bone)) continue;
    const std::string where = name + ": frames." + bone + ".";
    const Json& given = read_object(frames, bone, name + ": frames.");
    AnatomicalFrame frame;
    frame.origin_mm = read_point(given, "origin_mm", where);
    frame.right = read_direction(given, "right", where);
    frame.anterior = read_direction(given, "anterior", where);
    frame.superior = read_direction(given, "superior", where);
    check_frame(frame, name + ": frames." + bone);
    (std::string(bone) == "pelvis" ? user.pelvis : user.femur) = frame;
  }
  if (!user.pelvis && !user.femur) throw_error(name, ": frames: neither a pelvis nor a femur frame");
  return user;
}

UserFrame parse_landmarks(const Json& json, const std::string& name) {
  UserFrame user;
  user.source_kind = "landmarks";
  user.side = read_side(json, name);
  if (json.contains("hjc_mm")) user.hjc_mm = read_point(json, "hjc_mm", name + ": ");

  std::optional<EpicondylarLandmarks> femur;
  if (json.contains("femur_landmarks")) {
    const std::string where = name + ": femur_landmarks.";
    const Json& given = read_object(json, "femur_landmarks", name + ": ");
    femur.emplace();
    femur->head_centre_mm = read_point(given, "head_centre_mm", where);
    femur->medial_epicondyle_mm = read_point(given, "medial_epicondyle_mm", where);
    femur->lateral_epicondyle_mm = read_point(given, "lateral_epicondyle_mm", where);
    if (!user.side) {
      throw_error(name, ": side: missing (femur landmarks need it: the lateral epicondyle is on the subject's right "
                        "for a right femur only)");
    }
    user.femur = femur_epicondylar_frame(*femur, *user.side, name + ": femur_landmarks");
    if (!user.hjc_mm) user.hjc_mm = femur->head_centre_mm;
  }
  if (json.contains("pelvis_landmarks")) {
    const std::string where = name + ": pelvis_landmarks.";
    const Json& given = read_object(json, "pelvis_landmarks", name + ": ");
    AppLandmarks pelvis;
    pelvis.asis_right_mm = read_point(given, "asis_right_mm", where);
    pelvis.asis_left_mm = read_point(given, "asis_left_mm", where);
    pelvis.pubic_tubercle_right_mm = read_point(given, "pubic_tubercle_right_mm", where);
    pelvis.pubic_tubercle_left_mm = read_point(given, "pubic_tubercle_left_mm", where);
    // Origin: the HJC when known (the pelvic frame of the hip, anatomy/anatomical_frame.h), else
    // the ASIS midpoint.
    const Vec3 asis_mid = 0.5 * (pelvis.asis_right_mm + pelvis.asis_left_mm);
    user.pelvis = anterior_pelvic_plane_frame(pelvis, user.hjc_mm.value_or(asis_mid), name + ": pelvis_landmarks");
    if (femur && user.side) {
      // The head must lie on its side of the pelvis's mid-sagittal plane (through the ASIS midpoint).
      const double toward_right = (femur->head_centre_mm - asis_mid).dot(user.pelvis->right);
      if ((*user.side == Side::kRight) != (toward_right > 0.0)) {
        throw_error(name, ": side: ", side_name(*user.side), ", but the femoral head centre lies ",
                    std::abs(toward_right), " mm to the subject's ", toward_right > 0.0 ? "right" : "left",
                    " of the ASIS midpoint");
      }
    }
  }
  if (!user.pelvis && !user.femur) throw_error(name, ": neither pelvis_landmarks nor femur_landmarks");
  return user;
}

UserFrame parse_hip_model(const Json& json, const std::string& name) {
  UserFrame user;
  user.source_kind = "hip-model";
  const std::string where = name + ": ";
  if (json.contains("handedness")) {
    if (!json["handedness"].is_string()) throw_error(name, ": handedness: expected \"right\"");
    const std::string handedness = json["handedness"].get<std::string>();
    if (handedness != "right") {
      throw_error(name, ": handedness: '", handedness,
                  "': hipfai hip models are right hips (a left hip is mirrored, anatomy/side.h)");
    }
  }
  user.side = Side::kRight;
  user.hjc_mm = read_point(json, "hjc_mm", where);
  AnatomicalFrame frame;
  frame.origin_mm = *user.hjc_mm;
  frame.right = read_direction(json, "lateral", where);
  frame.superior = read_direction(json, "superior", where);
  frame.anterior = frame.superior.cross(frame.right);
  const double cosine = frame.right.dot(frame.superior);
  if (!(std::abs(cosine) <= kFrameOrthogonalityTolerance)) {
    throw_error(name, ": lateral and superior are not orthogonal (cosine ", cosine, ", at most ",
                kFrameOrthogonalityTolerance, ")");
  }
  frame.anterior.normalize();
  // The hip frame's motion axes (geometry/hip_frame.h) are its X, Y, Z: right, anterior, superior.
  const struct {
    const char* key;
    Vec3 expected;
    const char* axis;
  } motion_axes[] = {{"flexion_axis", frame.right, "lateral"},
                     {"adduction_axis", frame.anterior, "superior x lateral"},
                     {"internal_rotation_axis", frame.superior, "superior"}};
  for (const auto& motion_axis : motion_axes) {
    const Vec3 given = read_direction(json, motion_axis.key, where);
    const double off = (given - motion_axis.expected).norm();
    if (!(off <= kFrameOrthogonalityTolerance)) {
      throw_error(name, ": ", motion_axis.key, ": differs from ", motion_axis.axis, " by ", off, " (at most ",
                  kFrameOrthogonalityTolerance, ")");
    }
  }
  user.neck_axis = read_direction(json, "neck_axis", where);
  user.pelvis = frame;
  user.femur = frame;
  return user;
}

}  // namespace

AnatomicalFrame anterior_pelvic_plane_frame(const AppLandmarks& landmarks, const Vec3& origin_mm,
                                            const std::string& what) {
  const Vec3 across = landmarks.asis_right_mm - landmarks.asis_left_mm;
  if (!(across.norm() >= kMinLandmarkSeparationMm)) {
    throw_error(what, ": the two ASIS are ", across.norm(), " mm apart (at least ", kMinLandmarkSeparationMm,
                " mm)");
  }
  const Vec3 pubic_mid = 0.5 * (landmarks.pubic_tubercle_right_mm + landmarks.pubic_tubercle_left_mm);
  const Vec3 asis_mid = 0.5 * (landmarks.asis_right_mm + landmarks.asis_left_mm);
  AnatomicalFrame frame;
  frame.origin_mm = origin_mm;
  frame.right = across.normalized();
  const Vec3 up = asis_mid - pubic_mid;
  const Vec3 up_in_plane = up - up.dot(frame.right) * frame.right;
  if (!(up_in_plane.norm() >= kMinLandmarkSeparationMm)) {
    throw_error(what, ": the pubic tubercles' midpoint lies ", up_in_plane.norm(),
                " mm from the line through the ASIS (at least ", kMinLandmarkSeparationMm, " mm)");
  }
  frame.superior = up_in_plane.normalized();
  frame.anterior = frame.superior.cross(frame.right);
  return frame;
}

AnatomicalFrame femur_epicondylar_frame(const EpicondylarLandmarks& landmarks, Side side, const std::string& what) {
  const Vec3 across = landmarks.lateral_epicondyle_mm - landmarks.medial_epicondyle_mm;
  if (!(across.norm() >= kMinLandmarkSeparationMm)) {
    throw_error(what, ": the epicondyles are ", across.norm(), " mm apart (at least ", kMinLandmarkSeparationMm,
                " mm)");
  }
  const Vec3 knee = 0.5 * (landmarks.lateral_epicondyle_mm + landmarks.medial_epicondyle_mm);
  const Vec3 up = landmarks.head_centre_mm - knee;
  if (!(up.norm() >= kMinLandmarkSeparationMm)) {
    throw_error(what, ": the head centre is ", up.norm(), " mm from the epicondyles' midpoint (at least ",
                kMinLandmarkSeparationMm, " mm)");
  }
  AnatomicalFrame frame;
  frame.origin_mm = landmarks.head_centre_mm;
  frame.superior = up.normalized();
  const Vec3 toward_right = side == Side::kRight ? across : Vec3(-across);
  const Vec3 right_in_plane = toward_right - toward_right.dot(frame.superior) * frame.superior;
  if (!(right_in_plane.norm() >= kMinLandmarkSeparationMm)) {
    throw_error(what, ": the epicondyle line is parallel to the femoral axis (", right_in_plane.norm(),
                " mm across it, at least ", kMinLandmarkSeparationMm, " mm)");
  }
  frame.right = right_in_plane.normalized();
  frame.anterior = frame.superior.cross(frame.right);
  return frame;
}

UserFrame read_frame_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_error(path.string(), ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_frame_file(text.str(), path.string());
}

UserFrame parse_frame_file(const std::string& text, const std::string& name) {
  Json json;
  try {
    json = Json::parse(text);
  } catch (const Json::exception& e) {
    throw_error(name, ": invalid JSON: ", e.what());
  }
  if (!json.is_object()) throw_error(name, ": expected a JSON object");
  if (json.contains("format")) {
    if (!json["format"].is_string() || json["format"].get<std::string>() != "hipfai-hip-model") {
      throw_error(name, ": format: expected \"hipfai-hip-model\" (or no format key: frames or landmarks)");
    }
    return parse_hip_model(json, name);
  }
  const bool axes = json.contains("frames");
  const bool landmarks = json.contains("pelvis_landmarks") || json.contains("femur_landmarks");
  if (axes && landmarks) throw_error(name, ": both frames and landmarks: give one or the other");
  if (axes) return parse_axes(json, name);
  if (landmarks) return parse_landmarks(json, name);
  throw_error(name, ": no \"frames\", \"pelvis_landmarks\"/\"femur_landmarks\" or \"format\": "
                    "\"hipfai-hip-model\" (see anatomy/frame_file.h)");
}

UserFrame transformed(const UserFrame& frame, const Eigen::Affine3d& isometry) {
  const bool mirrored = isometry.linear().determinant() < 0.0;
  UserFrame out = frame;
  auto move = [&](AnatomicalFrame& f) {
    f.origin_mm = isometry * f.origin_mm;
    f.anterior = isometry.linear() * f.anterior;
    f.superior = isometry.linear() * f.superior;
    f.right = (mirrored ? -1.0 : 1.0) * (isometry.linear() * f.right);
  };
  if (out.pelvis) move(*out.pelvis);
  if (out.femur) move(*out.femur);
  if (out.hjc_mm) out.hjc_mm = isometry * *out.hjc_mm;
  if (out.neck_axis) out.neck_axis = isometry.linear() * *out.neck_axis;
  if (mirrored && out.side) out.side = *out.side == Side::kRight ? Side::kLeft : Side::kRight;
  return out;
}

}  // namespace hipfai::anatomy
