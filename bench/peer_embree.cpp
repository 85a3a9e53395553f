#include "bench/peer_embree.h"

#include "core/error.h"
#include "core/parallel.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <string>

namespace hipfai::bench {

struct EmbreeRadialCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> normals;  // outward unit normals of the fixed triangles (double)
  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

EmbreeRadialCaster::EmbreeRadialCaster(const geometry::TriMesh& fixed,
                                       const Eigen::Vector3d& centre, int build_threads)
    : impl_(std::make_unique<Impl>()) {
  impl_->centre = centre;
  const std::string config = build_threads > 0 ? "threads=" + std::to_string(build_threads) : "";
  impl_->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (impl_->device == nullptr) throw_error("embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), fixed.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), fixed.triangles.size()));
  for (std::size_t i = 0; i < fixed.vertices.size(); ++i) {
    const Eigen::Vector3d p = fixed.vertices[i] - centre;
    vertices[3 * i + 0] = static_cast<float>(p.x());
    vertices[3 * i + 1] = static_cast<float>(p.y());
    vertices[3 * i + 2] = static_cast<float>(p.z());
  }
  impl_->normals.resize(fixed.triangles.size());
  for (std::size_t t = 0; t < fixed.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + static_cast<std::size_t>(k)] = static_cast<unsigned>(fixed.triangles[t][static_cast<std::size_t>(k)]);
    impl_->normals[t] = geometry::triangle_area_normal(fixed, t);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
}

EmbreeRadialCaster::~EmbreeRadialCaster() = default;

contact::PenetrationResult EmbreeRadialCaster::query(const geometry::TriMesh& mobile, const Eigen::Isometry3d& pose,
                                                     contact::RadialConfiguration configuration,
                                                     int num_threads) const {
  contact::PenetrationResult result;
  const bool mobile_inside = configuration == contact::RadialConfiguration::kMobileInsideFixed;
  const int threads = num_threads < 1 ? 1 : num_threads;
  std::vector<std::vector<contact::PenetrationPair>> per_chunk(static_cast<std::size_t>(threads));
  parallel_chunks(
      mobile.vertices.size(), threads, [&](std::size_t begin, std::size_t end, int chunk) {
        auto& pairs = per_chunk[static_cast<std::size_t>(chunk)];
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (std::size_t v = begin; v < end; ++v) {
          const Eigen::Vector3d p = pose * mobile.vertices[v] - impl_->centre;
          const double r = p.norm();
          if (!(r > 0.0)) continue;
          const Eigen::Vector3d outward = p / r;
          const Eigen::Vector3d direction = mobile_inside ? -outward : outward;
          RTCRayHit hit;
          hit.ray.org_x = static_cast<float>(p.x());
          hit.ray.org_y = static_cast<float>(p.y());
          hit.ray.org_z = static_cast<float>(p.z());
          hit.ray.dir_x = static_cast<float>(direction.x());
          hit.ray.dir_y = static_cast<float>(direction.y());
          hit.ray.dir_z = static_cast<float>(direction.z());
          hit.ray.tnear = 0.0f;
          hit.ray.tfar = mobile_inside ? static_cast<float>(r) : std::numeric_limits<float>::infinity();
          hit.ray.mask = 0xFFFFFFFFu;
          hit.ray.flags = 0;
          hit.ray.time = 0.0f;
          hit.ray.id = 0;
          hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(impl_->scene, &context, &hit);
          if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
          const double distance = hit.ray.tfar;
          if (!(distance > 0.0)) continue;  // on the surface: not a penetration
          const double facing = impl_->normals[hit.hit.primID].dot(outward);
          // Going outwards from O: entering (facing < 0) below v, exiting (facing > 0) above v.
          const bool penetrates = mobile_inside ? facing < 0.0 : facing > 0.0;
          if (!penetrates) continue;
          contact::PenetrationPair pair;
          pair.mobile_vertex = static_cast<std::int32_t>(v);
          pair.fixed_triangle = static_cast<std::int32_t>(hit.hit.primID);
          pair.depth_mm = distance;
          pairs.push_back(pair);
        }
      });
  for (auto& pairs : per_chunk) result.pairs.insert(result.pairs.end(), pairs.begin(), pairs.end());
  return result;
}

}  // namespace hipfai::bench
