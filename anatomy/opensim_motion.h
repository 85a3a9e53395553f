// hipfai — reading a hip's joint angles from an OpenSim motion file (.mot, .sto), for the
// clinical motions of `hipfai assess`.
//
// Format (OpenSim's Storage files, as OpenSim/Common/Storage.cpp reads and writes them):
//   a header of lines up to one reading `endheader`: a name line (the first line, or `name <text>`),
//   `version=<int>` (absent in the older SIMM-style motion files: version 0), `nRows=<int>` (also
//   `nr`, `datarows`), `nColumns=<int>` (also `nc`, `datacolumns`; the time column counts),
//   `inDegrees=yes|no`, and any other lines (other key=value pairs, `# comments`, blank lines),
//   which are skipped; a key ends at the first space, tab or '='.
//   Then (after blank lines) the column labels, tab-separated (whitespace-separated when the line
//   has no tab), the first one `time`; then one row per line, numbers separated by tabs or spaces.
//
// Units: `inDegrees=yes` / `no` (or, in version 0 files, "Angles are in degrees." / "... radians.")
// say it. With neither, OpenSim reads a version-0 .mot file (a SIMM motion file) in degrees; so
// does this reader. Any other file without a units line is refused rather than guessed.
// (OpenSim itself lets a version-0 .mot file's SIMM rule override an explicit `inDegrees=no`;
// here the explicit line wins.)
//
// Columns: hip_flexion_<s>, hip_adduction_<s>, hip_rotation_<s> with s = r or l, as the gait
// models name the hip's coordinates (gait2392: Delp et al. 1990, IEEE Trans Biomed Eng 37:757;
// Rajagopal et al. 2016, IEEE Trans Biomed Eng 63:2068). A label may also be a state path ending
// in /hip_flexion_r/value (OpenSim 4 states files). Other columns are read as numbers (so a
// malformed row is still found) and otherwise ignored.
//
// Signs and sequence, and how they map onto hipfai's (geometry/hip_frame.h). Both models put the
// hip in a CustomJoint between the pelvis frame (X anterior, Y superior, Z to the subject's right)
// and the femur frame, whose SpatialTransform is rotation1 = hip_flexion about Z, rotation2 =
// hip_adduction about X, rotation3 = hip_rotation about Y for the right hip; for the left hip about
// Z, -X, -Y (gait2392 writes the negated axes, Rajagopal's model the same axes with a -1
// coefficient). Simbody composes a CustomJoint's rotations as a body-fixed sequence,
// R = R(q1, a1) R(q2, a2) R(q3, a3) (MobilizedBody::FunctionBased). So for a right hip, positive
// values are flexion (knee anterior), adduction (knee medial) and internal rotation (anterior
// femur turning medially). Relabelling OpenSim's (Z, X, Y) as hipfai's (X lateral, Y anterior,
// Z superior) for a right hip gives R = Rx(flexion) Ry(adduction) Rz(internal rotation): exactly
// hipfai's PoseSequence::kJointCoordinateSystem, so the three angles are copied unchanged. For a
// left hip, mirroring through the sagittal plane (anatomy/side.h: left hips are measured as
// mirrored right hips) maps a rotation about axis a by q to one about -(M a) by q (M the mirror),
// turning the left joint's Z, -X, -Y into Z, X, Y: the same right-hip sequence with the same
// angles. Hence both sides' angles are the mirrored right hip's (flexion, adduction, internal
// rotation) as they stand, and poses are in the hip frame of the (mirrored) right hip.
#pragma once

#include "anatomy/side.h"
#include "geometry/hip_frame.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::anatomy {

// The hip's angles over time, as read from a motion file.
struct JointAngleSeries {
  std::string name;                       // the file header's name (empty when it has none)
  Side side = Side::kRight;               // whose hip columns were read
  std::vector<double> time_s;             // the `time` column, strictly increasing, s
  std::vector<geometry::HipPoseDeg> poses;  // one per row: (flexion, adduction, internal rotation), deg
};

// Reads `path` (parse_opensim_motion with the path as the name). Throws hipfai::Error naming the
// file when it cannot be opened.
JointAngleSeries read_opensim_motion(const std::filesystem::path& path, std::optional<Side> side = std::nullopt);

// Parses the text of a motion file. `name_for_messages` names the file in error messages, and its
// extension (.mot) decides the SIMM-file units rule above. `side`: which hip's columns to read;
// without it, the side whose three columns are all present (an error if both or neither are).
// Throws hipfai::Error "<name>:<line>: <problem>" for: no `endheader`, a malformed version, row or
// column count, or inDegrees value, no units line (see above), a first label other than `time`,
// missing or repeated hip columns, a row with the wrong number of fields, a field that is not a
// number, a non-finite time or hip angle, an angle beyond 180 deg after conversion (mostly radians
// read as degrees or the reverse), a time not after the previous row's, no rows, or a row or
// column count differing from the header's.
JointAngleSeries parse_opensim_motion(const std::string& text, const std::string& name_for_messages,
                                      std::optional<Side> side = std::nullopt);

}  // namespace hipfai::anatomy
