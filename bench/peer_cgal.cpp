#include "bench/peer_cgal.h"

#include "core/parallel.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <variant>

namespace hipfai::bench {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Ray = Kernel::Ray_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;

Point to_point(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }

}  // namespace

struct CgalRadialCaster::Impl {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::vector<Triangle> triangles;  // relative to the centre
  std::vector<Eigen::Vector3d> normals;
  Tree tree;
};

CgalRadialCaster::CgalRadialCaster(const geometry::TriMesh& fixed, const Eigen::Vector3d& centre)
    : impl_(std::make_unique<Impl>()) {
  impl_->centre = centre;
  impl_->triangles.reserve(fixed.triangles.size());
  impl_->normals.reserve(fixed.triangles.size());
  for (std::size_t t = 0; t < fixed.triangles.size(); ++t) {
    const auto& tri = fixed.triangles[t];
    impl_->triangles.emplace_back(to_point(fixed.vertices[static_cast<std::size_t>(tri[0])] - centre),
                                  to_point(fixed.vertices[static_cast<std::size_t>(tri[1])] - centre),
                                  to_point(fixed.vertices[static_cast<std::size_t>(tri[2])] - centre));
    impl_->normals.push_back(geometry::triangle_area_normal(fixed, t));
  }
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();  // the tree is otherwise built lazily by the first (concurrent) query
}

CgalRadialCaster::~CgalRadialCaster() = default;

contact::PenetrationResult CgalRadialCaster::query(const geometry::TriMesh& posed_mobile,
                                                   contact::RadialConfiguration configuration,
                                                   int num_threads) const {
  contact::PenetrationResult result;
  const bool mobile_inside = configuration == contact::RadialConfiguration::kMobileInsideFixed;
  const int threads = num_threads < 1 ? 1 : num_threads;
  std::vector<std::vector<contact::PenetrationPair>> per_chunk(static_cast<std::size_t>(threads));
  parallel_chunks(
      posed_mobile.vertices.size(), threads, [&](std::size_t begin, std::size_t end, int chunk) {
        auto& pairs = per_chunk[static_cast<std::size_t>(chunk)];
        for (std::size_t v = begin; v < end; ++v) {
          const Eigen::Vector3d p = posed_mobile.vertices[v] - impl_->centre;
          const double r = p.norm();
          if (!(r > 0.0)) continue;
          const Eigen::Vector3d outward = p / r;
          const Eigen::Vector3d target = mobile_inside ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(2.0 * p);
          const Ray ray(to_point(p), to_point(target));
          const auto hit = impl_->tree.first_intersection(ray);
          if (!hit) continue;
          double distance = 0.0;
          if (const Point* point = boost::get<Point>(&hit->first)) {
            distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(*point, ray.source())));
          } else {
            continue;  // the ray lies in the triangle's plane: no crossing (as ray_triangle.h)
          }
          if (!(distance > 0.0)) continue;
          if (mobile_inside && !(distance < r)) continue;  // only crossings in front of O
          const std::size_t t = static_cast<std::size_t>(hit->second - impl_->triangles.cbegin());
          const double facing = impl_->normals[t].dot(outward);
          const bool penetrates = mobile_inside ? facing < 0.0 : facing > 0.0;
          if (!penetrates) continue;
          contact::PenetrationPair pair;
          pair.mobile_vertex = static_cast<std::int32_t>(v);
          pair.fixed_triangle = static_cast<std::int32_t>(t);
          pair.depth_mm = distance;
          pairs.push_back(pair);
        }
      });
  for (auto& pairs : per_chunk) result.pairs.insert(result.pairs.end(), pairs.begin(), pairs.end());
  return result;
}

}  // namespace hipfai::bench
