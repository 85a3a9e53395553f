#include "fem/fem_results.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/version.h"

#include <hdf5.h>

#include <array>

namespace hipfai::fem {

namespace {

void set_string_attribute(hid_t object, const char* name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.empty() ? 1 : value.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attribute = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attribute, type, value.empty() ? "" : value.c_str());
  H5Aclose(attribute);
  H5Sclose(space);
  H5Tclose(type);
}

void write_dataset(hid_t group, const std::string& name, hid_t type, const void* data,
                   const std::vector<hsize_t>& dims, const std::string& unit) {
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t dataset = H5Dcreate2(group, name.c_str(), type == H5T_NATIVE_INT ? H5T_STD_I32LE : H5T_IEEE_F64LE,
                                   space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (dims[0] > 0) H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  set_string_attribute(dataset, "unit", unit);
  H5Dclose(dataset);
  H5Sclose(space);
}

}  // namespace

FemResultsWriter::FemResultsWriter(std::string file, std::vector<std::string> body_names,
                                   unsigned int moving_body)
    : file_(std::move(file)), body_names_(std::move(body_names)), moving_body_(moving_body) {
  write();  // fails early, before any solve, on an unwritable path
}

void FemResultsWriter::append(const MotionStep& step, const ContactResult& result) {
  steps_.push_back(step);
  results_.push_back(result);
  write();
}

void FemResultsWriter::write() const {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become our one-line messages
  // Written under a temporary name and renamed when complete: a results file that exists is
  // whole, even if the run is killed while it is being rewritten.
  AtomicFile temporary(file_);
  const hid_t file = H5Fcreate(temporary.partial_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) throw_error(file_, ": cannot create the HDF5 results file");
  const hsize_t n = results_.size();
  const hsize_t bodies = body_names_.size();
  const hid_t root_space = H5Screate(H5S_SCALAR);
  const int version = 3;
  const hid_t version_attribute =
      H5Acreate2(file, "layout_version", H5T_STD_I32LE, root_space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(version_attribute, H5T_NATIVE_INT, &version);
  H5Aclose(version_attribute);
  H5Sclose(root_space);
  std::string names;
  for (const std::string& name : body_names_) names += (names.empty() ? "" : ";") + name;
  set_string_attribute(file, "bodies", names);
  set_string_attribute(file, "code_version", std::string(kVersion) + " (" + kGitSha + ")");
  set_string_attribute(file, "units", "mm, N, MPa, s");

  const hid_t group = H5Gcreate2(file, "steps", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<int> status, newton, solves, cg, sub_steps, cutbacks, cells;
  std::vector<double> dofs;
  std::vector<double> wall, rotation, force, translation, resultant, max_p, mean_p, area, penetration,
      max_vm, p95_vm, radius, ball_vm, ball_vm_position, ball_p, ball_p_position, max_p_position;
  for (std::size_t k = 0; k < results_.size(); ++k) {
    const ContactResult& r = results_[k];
    status.push_back(static_cast<int>(r.status));
    newton.push_back(static_cast<int>(r.statistics.active_set_iterations));
    solves.push_back(static_cast<int>(r.statistics.linear_solves));
    cg.push_back(static_cast<int>(r.statistics.linear_iterations));
    sub_steps.push_back(static_cast<int>(r.statistics.sub_steps));
    cutbacks.push_back(static_cast<int>(r.statistics.cutbacks));
    cells.push_back(static_cast<int>(r.statistics.n_cells));
    dofs.push_back(static_cast<double>(r.statistics.n_dofs));
    wall.push_back(r.statistics.wall_time_s);
    for (unsigned i = 0; i < 3; ++i) {
      for (unsigned j = 0; j < 3; ++j) rotation.push_back(steps_[k].rotation[i][j]);
    }
    dealii::Tensor<1, 3> total;
    for (const auto& f : r.pair_force_n) total += f;
    dealii::Tensor<1, 3> t;
    if (moving_body_ < r.rigid_translation_mm.size()) t = r.rigid_translation_mm[moving_body_];
    for (unsigned d = 0; d < 3; ++d) {
      force.push_back(steps_[k].force_n[d]);
      translation.push_back(t[d]);
      resultant.push_back(total[d]);
    }
    max_p.push_back(r.peaks.max_pressure_mpa);
    radius.push_back(r.peaks.peak_average_radius_mm);
    ball_p.push_back(r.peaks.ball_peak_pressure_mpa);
    for (unsigned d = 0; d < 3; ++d) {
      ball_p_position.push_back(r.peaks.ball_peak_pressure_position_mm[d]);
      max_p_position.push_back(r.peaks.max_pressure_position_mm[d]);
    }
    mean_p.push_back(r.peaks.mean_pressure_mpa);
    area.push_back(r.peaks.contact_area_mm2);
    penetration.push_back(r.peaks.max_penetration_mm);
    for (hsize_t b = 0; b < bodies; ++b) {
      max_vm.push_back(b < r.peaks.max_von_mises_mpa.size() ? r.peaks.max_von_mises_mpa[b] : 0.0);
      p95_vm.push_back(b < r.peaks.p95_von_mises_mpa.size() ? r.peaks.p95_von_mises_mpa[b] : 0.0);
      ball_vm.push_back(b < r.peaks.ball_peak_von_mises_mpa.size() ? r.peaks.ball_peak_von_mises_mpa[b] : 0.0);
      const dealii::Point<3> centre =
          b < r.peaks.ball_peak_von_mises_position_mm.size() ? r.peaks.ball_peak_von_mises_position_mm[b] : dealii::Point<3>();
      for (unsigned d = 0; d < 3; ++d) ball_vm_position.push_back(centre[d]);
    }
  }
  write_dataset(group, "status", H5T_NATIVE_INT, status.data(), {n}, "1");
  write_dataset(group, "active_set_iterations", H5T_NATIVE_INT, newton.data(), {n}, "1");
  write_dataset(group, "linear_solves", H5T_NATIVE_INT, solves.data(), {n}, "1");
  write_dataset(group, "linear_iterations", H5T_NATIVE_INT, cg.data(), {n}, "1");
  write_dataset(group, "sub_steps", H5T_NATIVE_INT, sub_steps.data(), {n}, "1");
  write_dataset(group, "cutbacks", H5T_NATIVE_INT, cutbacks.data(), {n}, "1");
  write_dataset(group, "n_cells", H5T_NATIVE_INT, cells.data(), {n}, "1");
  write_dataset(group, "n_dofs", H5T_NATIVE_DOUBLE, dofs.data(), {n}, "1");
  write_dataset(group, "wall_time_s", H5T_NATIVE_DOUBLE, wall.data(), {n}, "s");
  write_dataset(group, "rotation", H5T_NATIVE_DOUBLE, rotation.data(), {n, 3, 3}, "1");
  write_dataset(group, "applied_force_n", H5T_NATIVE_DOUBLE, force.data(), {n, 3}, "N");
  write_dataset(group, "femur_translation_mm", H5T_NATIVE_DOUBLE, translation.data(), {n, 3}, "mm");
  write_dataset(group, "contact_resultant_n", H5T_NATIVE_DOUBLE, resultant.data(), {n, 3}, "N");
  write_dataset(group, "max_pressure_mpa", H5T_NATIVE_DOUBLE, max_p.data(), {n}, "MPa");
  write_dataset(group, "mean_pressure_mpa", H5T_NATIVE_DOUBLE, mean_p.data(), {n}, "MPa");
  write_dataset(group, "contact_area_mm2", H5T_NATIVE_DOUBLE, area.data(), {n}, "mm^2");
  write_dataset(group, "max_penetration_mm", H5T_NATIVE_DOUBLE, penetration.data(), {n}, "mm");
  write_dataset(group, "max_von_mises_mpa", H5T_NATIVE_DOUBLE, max_vm.data(), {n, bodies}, "MPa");
  write_dataset(group, "p95_von_mises_mpa", H5T_NATIVE_DOUBLE, p95_vm.data(), {n, bodies}, "MPa");
  write_dataset(group, "max_pressure_position_mm", H5T_NATIVE_DOUBLE, max_p_position.data(), {n, 3}, "mm");
  write_dataset(group, "peak_average_radius_mm", H5T_NATIVE_DOUBLE, radius.data(), {n}, "mm");
  write_dataset(group, "ball_peak_von_mises_mpa", H5T_NATIVE_DOUBLE, ball_vm.data(), {n, bodies}, "MPa");
  write_dataset(group, "ball_peak_von_mises_position_mm", H5T_NATIVE_DOUBLE, ball_vm_position.data(),
                {n, bodies, 3}, "mm");
  write_dataset(group, "ball_peak_pressure_mpa", H5T_NATIVE_DOUBLE, ball_p.data(), {n}, "MPa");
  write_dataset(group, "ball_peak_pressure_position_mm", H5T_NATIVE_DOUBLE, ball_p_position.data(), {n, 3}, "mm");
  H5Gclose(group);
  if (H5Fclose(file) < 0) throw_error(file_, ": cannot write the HDF5 results file");
  temporary.commit();
}

}  // namespace hipfai::fem
