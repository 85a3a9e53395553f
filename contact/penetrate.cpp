#include "contact/penetrate.h"

#include "contact/cylindrical_cache_io.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_spans.h"
#include "contact/radial_table_io.h"
#include "core/hash.h"

#include <chrono>
#include <cstdint>
#include <optional>
#include <utility>

namespace hipfai::contact {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The file `name` in the cache folder, the folder made when it does not exist yet (a run from an
// empty working directory); a folder that cannot be made is reported by the write that follows.
std::filesystem::path cache_file(const std::filesystem::path& cache_dir, const std::string& name) {
  std::error_code error;
  std::filesystem::create_directories(cache_dir, error);
  return cache_dir / name;
}

// The pose cache of M about `axis` through the centre: loaded from the cache folder when an
// identical one was built before, else built (table + cache) and saved.
CylindricalPoseCache pose_cache_for(const PenetrationRequest& request, const Vec3& axis, PreprocessingCount& count) {
  std::filesystem::path file;
  if (!request.cache_dir.empty()) {
    Hasher key;
    key.add(request.fixed_key).add(request.mobile_key);
    key.add(request.centre.x()).add(request.centre.y()).add(request.centre.z());
    key.add(axis.x()).add(axis.y()).add(axis.z());
    file = cache_file(request.cache_dir, "cylindrical-pose-cache-" + key.hex() + ".bin");
    if (auto cached = load_pose_cache(file)) {
      ++count.loaded;
      return std::move(*cached);
    }
  }
  CylindricalQueryOptions query;
  query.num_threads = request.num_threads;
  query.touching_mm = request.touching_mm;
  CylindricalTableOptions table_options;
  table_options.angular_index = false;  // the pose cache reads every crossing
  const auto table = CylindricalTable::build(*request.fixed, request.centre, axis, table_options, request.mobile);
  CylindricalPoseCache cache(table, *request.mobile, query);
  ++count.built;
  if (!file.empty()) save_pose_cache(cache, file);
  return cache;
}

// F's radial table about the centre, loaded or built (and saved) as the pose caches are.
RadialTable radial_table_for(const PenetrationRequest& request, PreprocessingCount& count) {
  std::filesystem::path file;
  if (!request.cache_dir.empty()) {
    Hasher key;
    key.add(request.fixed_key).add(request.centre.x()).add(request.centre.y()).add(request.centre.z());
    key.add(static_cast<std::int64_t>(request.radial_table.mapping)).add(request.radial_table.table_size);
    file = cache_file(request.cache_dir, "radial-table-" + key.hex() + ".bin");
    if (auto cached = load_radial_table(file); cached && cached->num_triangles == request.fixed->num_triangles()) {
      ++count.loaded;
      compute_radial_spans(*cached, *request.fixed);  // not stored in the file: derived from F
      return std::move(*cached);
    }
  }
  RadialTable table = build_radial_table(*request.fixed, request.centre, request.radial_table);
  ++count.built;
  if (!file.empty()) save_radial_table(table, file);
  return table;
}

// Keeps the first rejected query's message in the response; true while every query is valid.
bool accept(const PenetrationResult& result, PenetrationResponse& response) {
  if (result.status != QueryStatus::kInvalidInput) return true;
  response.status = QueryStatus::kInvalidInput;
  response.message = result.message;
  return false;
}

// Curvilinear depth, one pose cache per distinct axis (in the order the axes first appear).
bool curvilinear_steps(const PenetrationRequest& request, PenetrationResponse& response) {
  const std::vector<PenetrationStep>& steps = request.steps;
  std::vector<bool> done(steps.size(), false);
  for (std::size_t first = 0; first < steps.size(); ++first) {
    if (done[first]) continue;
    const Vec3 axis = steps[first].axis;
    const auto start = Clock::now();
    const CylindricalPoseCache cache = pose_cache_for(request, axis, response.curvilinear_preprocessing);
    response.curvilinear_preprocessing_ms += ms_since(start);
    for (std::size_t k = first; k < steps.size(); ++k) {
      if (done[k] || steps[k].axis != axis) continue;
      done[k] = true;
      const auto query_start = Clock::now();
      response.steps[k].curvilinear = cache.query(steps[k].angle_deg);
      response.steps[k].curvilinear_ms = ms_since(query_start);
      if (!accept(response.steps[k].curvilinear, response)) return false;
    }
  }
  return true;
}

// Radial depth: F's table once, M prepared once for every step.
bool radial_steps(const PenetrationRequest& request, PenetrationResponse& response) {
  const auto start = Clock::now();
  const RadialTable table = radial_table_for(request, response.radial_preprocessing);
  RadialQueryOptions options;
  options.configuration = request.radial_configuration;
  options.rule = request.radial_rule;
  options.num_threads = request.num_threads;
  const RadialPoseQuery prepared(table, *request.fixed, *request.mobile, options);
  response.radial_preprocessing_ms = ms_since(start);
  for (std::size_t k = 0; k < request.steps.size(); ++k) {
    const auto query_start = Clock::now();
    response.steps[k].radial = prepared.query_rotation(request.steps[k].rotation);
    response.steps[k].radial_ms = ms_since(query_start);
    if (!accept(response.steps[k].radial, response)) return false;
  }
  return true;
}

}  // namespace

PenetrationResponse penetrate(const PenetrationRequest& request) {
  PenetrationResponse response;
  if (request.fixed == nullptr || request.mobile == nullptr) {
    response.status = QueryStatus::kInvalidInput;
    response.message = "penetrate: the request has no fixed or no mobile mesh";
    return response;
  }
  response.steps.resize(request.steps.size());
  if (request.steps.empty()) return response;
  if (request.curvilinear && !curvilinear_steps(request, response)) return response;
  if (request.radial) radial_steps(request, response);
  return response;
}

}  // namespace hipfai::contact
