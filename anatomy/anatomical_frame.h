// hipfai — an anatomical frame of a bone: an origin and the subject's right, anterior and superior
// directions, in the coordinates of the input meshes (mm, unit vectors).
//
// "right", "anterior", "superior" name the SUBJECT's directions for either side (a left hip's lateral
// is -right). Pelvis: the anterior pelvic plane frame (origin at the HJC for the hip's use). Femur
// (Wu et al. 2002, ISB): origin at the HJC, superior along the mechanical axis (knee centre to HJC)
// when the distal femur is there, else along the shaft axis; right perpendicular to it, in the plane
// of the transepicondylar axis.
//
// For the right-hip machinery (geometry/hip_frame.h: +X lateral, +Y anterior, +Z superior), a right
// hip's hip axes are the columns (right, anterior, superior); a left hip is mirrored first
// (anatomy/side.h).
#pragma once

#include "geometry/tri_mesh.h"

#include <Eigen/Core>

namespace hipfai::anatomy {

struct AnatomicalFrame {
  geometry::Vec3 origin_mm = geometry::Vec3::Zero();
  geometry::Vec3 right = geometry::Vec3::UnitX();
  geometry::Vec3 anterior = geometry::Vec3::UnitY();
  geometry::Vec3 superior = geometry::Vec3::UnitZ();

  // Columns (right, anterior, superior): maps frame coordinates to mesh coordinates.
  Eigen::Matrix3d axes() const {
    Eigen::Matrix3d m;
    m.col(0) = right;
    m.col(1) = anterior;
    m.col(2) = superior;
    return m;
  }
};

}  // namespace hipfai::anatomy
