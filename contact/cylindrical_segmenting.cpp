#include "contact/cylindrical_segmenting.h"

#include "contact/detail/ablation.h"

#include "core/numbers.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

namespace hipfai::contact {
namespace {

using hipfai::kDegPerRad;
// Candidate arcs are widened by this on both sides: far more than the rounding of a pose angle
// (|theta0 + angle| up to kIndexedAngleLimitRad: ~1e-13 rad), far less than any real arc.
constexpr double kArcMarginRad = 1e-12;
constexpr double kIndexedAngleLimitRad = 1e3;

bool finite_vertices(const geometry::TriMesh& mesh) {
  return std::all_of(mesh.vertices.begin(), mesh.vertices.end(),
                     [](const Vec3& p) { return p.allFinite(); });
}

PenetrationResult invalid(std::string message) {
  PenetrationResult result;
  result.status = QueryStatus::kInvalidInput;
  result.message = std::move(message);
  return result;
}

// Joins per-chunk outputs in chunk order: chunks are contiguous vertex ranges, so the result is
// sorted by mobile vertex without a sort.
PenetrationResult join_chunks(std::vector<std::vector<PenetrationPair>>& chunks) {
  PenetrationResult result;
  std::size_t total = 0;
  for (const auto& chunk : chunks) total += chunk.size();
  result.pairs.reserve(total);
  for (auto& chunk : chunks) result.pairs.insert(result.pairs.end(), chunk.begin(), chunk.end());
  return result;
}

// The one-pass test of mobile vertex v at `position` (fixed frame): its pair into `out` if it
// penetrates.
void visit_vertex(const CylindricalTable& table, std::int32_t v, const Vec3& position,
                  const CylindricalQueryOptions& options, const detail::CylindricalAblation& ablation,
                  std::vector<PenetrationPair>& out) {
  const Vec3 local = table.frame().to_local(position);
  if (!table.distance_may_touch(local.norm())) return;
  // r and z first: most circles meet an empty cell, and then no angle is needed.
  if (!table.has_candidates(std::hypot(local.x(), local.y()), local.z())) return;
  const Cylindrical cyl = to_cylindrical(local);
  if (ablation.outside_regions && table.outside_every_shell(cyl.r, cyl.z, cyl.theta)) return;
  const NearestCrossing nearest = ablation.angular_walk
                                      ? table.nearest_crossing(cyl.r, cyl.z, cyl.theta)
                                      : table.nearest_crossing_of_every_candidate(cyl.r, cyl.z, cyl.theta);
  if (!nearest.found()) return;
  if (arc_verdict(cyl.r, cyl.z, cyl.theta, nearest.crossing_theta_rad, table.local_normal(nearest.triangle),
                  options.touching_mm) != ArcVerdict::kPenetrating) {
    return;
  }
  out.push_back({v, nearest.triangle, cyl.r * nearest.abs_delta_rad, nearest.abs_delta_rad * kDegPerRad});
}

std::optional<PenetrationResult> no_overlap(const CylindricalTable& table) {
  if (table.status() != QueryStatus::kNoOverlap) return std::nullopt;
  PenetrationResult result;
  result.status = QueryStatus::kNoOverlap;
  return result;
}

// Calls visit_cluster(cluster, out) for every cluster of `mobile`, in blocks of 32 clusters taken
// dynamically by the pool, each block with its own output; the pairs joined and sorted by mobile
// vertex (clusters visit vertices out of order).
template <typename VisitCluster>
PenetrationResult cluster_pass(const VertexClusters& mobile, const CylindricalQueryOptions& options,
                               VisitCluster&& visit_cluster) {
  const std::span<const VertexCluster> clusters = mobile.clusters();
  constexpr std::size_t kClustersPerBlock = 32;
  std::vector<std::vector<PenetrationPair>> chunks((clusters.size() + kClustersPerBlock - 1) / kClustersPerBlock);
  parallel_blocks(chunks.size(), resolve_threads(options.num_threads), 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t block = first; block < last; ++block) {
      const std::size_t end = std::min(clusters.size(), (block + 1) * kClustersPerBlock);
      for (std::size_t k = block * kClustersPerBlock; k < end; ++k) visit_cluster(clusters[k], chunks[block]);
    }
  });
  PenetrationResult result = join_chunks(chunks);
  std::sort(result.pairs.begin(), result.pairs.end(),
            [](const PenetrationPair& a, const PenetrationPair& b) { return a.mobile_vertex < b.mobile_vertex; });
  return result;
}

// The one-pass query cluster by cluster (CylindricalTable::mobile_clusters): a cluster's vertices
// are posed into a buffer, and the ball about their bounding box, widened far beyond the rounding
// of the box and of the frame change, is tested before any of them.
template <typename Position>
PenetrationResult one_pass_by_clusters(const CylindricalTable& table, Position&& position,
                                       const CylindricalQueryOptions& options,
                                       const detail::CylindricalAblation& ablation) {
  const VertexClusters& mobile = table.mobile_clusters();
  const double scale = 1.0 + table.frame().centre.norm();
  return cluster_pass(mobile, options, [&](const VertexCluster& cluster, std::vector<PenetrationPair>& out) {
    thread_local std::vector<Vec3> posed;
    posed.clear();
    for (std::uint32_t i = cluster.first; i < cluster.last; ++i) {
      posed.push_back(position(static_cast<std::size_t>(mobile.mesh_index(i))));
    }
    Vec3 lo = posed.front(), hi = posed.front();
    for (const Vec3& p : posed) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Vec3 middle = 0.5 * (lo + hi);
    const double radius = 0.5 * (hi - lo).norm();
    if (!table.ball_may_touch(table.frame().to_local(middle), radius + 1e-9 * (scale + middle.norm() + radius))) {
      return;
    }
    for (std::uint32_t i = cluster.first; i < cluster.last; ++i) {
      visit_vertex(table, mobile.mesh_index(i), posed[i - cluster.first], options, ablation, out);
    }
  });
}

// The one-pass query over `count` mobile vertices, vertex v at position(v) in the fixed frame.
template <typename Position>
PenetrationResult one_pass(const CylindricalTable& table, std::size_t count, Position&& position,
                           const CylindricalQueryOptions& options, const detail::CylindricalAblation& ablation) {
  if (std::optional<PenetrationResult> answer = no_overlap(table)) return std::move(*answer);
  if (ablation.mobile_clusters && count > 0 && table.mobile_clusters().num_vertices() == count) {
    return one_pass_by_clusters(table, position, options, ablation);
  }
  const int threads = resolve_threads(options.num_threads);
  // Blocks of vertices taken dynamically: the circles that need a walk cluster in a few parts of
  // the mesh, so equal contiguous chunks would leave a thread idle. Blocks join in order.
  constexpr std::size_t kBlock = 1024;
  std::vector<std::vector<PenetrationPair>> chunks((count + kBlock - 1) / kBlock);
  parallel_blocks(chunks.size(), threads, 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t block = first; block < last; ++block) {
      const std::size_t end = std::min(count, (block + 1) * kBlock);
      for (std::size_t v = block * kBlock; v < end; ++v) {
        visit_vertex(table, static_cast<std::int32_t>(v), position(v), options, ablation, chunks[block]);
      }
    }
  });
  return join_chunks(chunks);
}

}  // namespace

PenetrationResult cylindrical_segmenting(const CylindricalTable& table,
                                         const geometry::TriMesh& posed_mobile,
                                         const CylindricalQueryOptions& options) {
  return detail::cylindrical_segmenting(table, posed_mobile, options, {});
}

PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const geometry::TriMesh& mobile,
                                         const Eigen::Isometry3d& pose,
                                         const CylindricalQueryOptions& options) {
  return detail::cylindrical_segmenting(table, mobile, pose, options, {});
}

PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const VertexClusters& mobile,
                                         const Eigen::Isometry3d& pose, const CylindricalQueryOptions& options) {
  return detail::cylindrical_segmenting(table, mobile, pose, options, {});
}

PenetrationResult detail::cylindrical_segmenting(const CylindricalTable& table,
                                                 const geometry::TriMesh& posed_mobile,
                                                 const CylindricalQueryOptions& options,
                                                 const CylindricalAblation& ablation) {
  if (table.status() == QueryStatus::kInvalidInput) return invalid(table.message());
  if (!finite_vertices(posed_mobile)) return invalid("mobile mesh has a non-finite coordinate");
  return one_pass(table, posed_mobile.vertices.size(),
                  [&](std::size_t v) -> const Vec3& { return posed_mobile.vertices[v]; }, options, ablation);
}

PenetrationResult detail::cylindrical_segmenting(const CylindricalTable& table, const geometry::TriMesh& mobile,
                                                 const Eigen::Isometry3d& pose,
                                                 const CylindricalQueryOptions& options,
                                                 const CylindricalAblation& ablation) {
  if (table.status() == QueryStatus::kInvalidInput) return invalid(table.message());
  if (!finite_vertices(mobile)) return invalid("mobile mesh has a non-finite coordinate");
  if (!pose.matrix().allFinite()) return invalid("pose has a non-finite entry");
  return one_pass(table, mobile.vertices.size(), [&](std::size_t v) -> Vec3 { return pose * mobile.vertices[v]; },
                  options, ablation);
}

PenetrationResult detail::cylindrical_segmenting(const CylindricalTable& table, const VertexClusters& mobile,
                                                 const Eigen::Isometry3d& pose, const CylindricalQueryOptions& options,
                                                 const CylindricalAblation& ablation) {
  if (table.status() == QueryStatus::kInvalidInput) return invalid(table.message());
  if (!pose.matrix().allFinite()) return invalid("pose has a non-finite entry");
  if (std::optional<PenetrationResult> answer = no_overlap(table)) return std::move(*answer);
  const AxisFrame& frame = table.frame();
  // The posed sphere of a cluster holds its posed vertices up to the rounding of the two posings
  // and of the frame change, far below this widening.
  const double scale = 1.0 + pose.translation().norm() + frame.centre.norm();
  return cluster_pass(mobile, options, [&](const VertexCluster& cluster, std::vector<PenetrationPair>& out) {
    const double margin = 1e-9 * (scale + cluster.centre.norm() + cluster.radius_mm);
    if (!table.ball_may_touch(frame.to_local(pose * cluster.centre), cluster.radius_mm + margin)) return;
    for (std::size_t i = cluster.first; i < cluster.last; ++i) {
      visit_vertex(table, mobile.mesh_index(i), pose * mobile.vertex(i), options, ablation, out);
    }
  });
}

PenetrationResult cylindrical_segmenting(const geometry::TriMesh& fixed,
                                         const geometry::TriMesh& posed_mobile,
                                         const Vec3& centre, const Vec3& axis,
                                         const CylindricalQueryOptions& options,
                                         const CylindricalTableOptions& table_options) {
  if (!finite_vertices(posed_mobile)) return invalid("mobile mesh has a non-finite coordinate");
  if (posed_mobile.vertices.empty()) return invalid("mobile mesh is empty");
  const CylindricalTable table =
      CylindricalTable::build(fixed, centre, axis, table_options, &posed_mobile);
  return cylindrical_segmenting(table, posed_mobile, options);
}

CylindricalPoseCache::CylindricalPoseCache(const CylindricalTable& table,
                                           const geometry::TriMesh& mobile,
                                           const CylindricalQueryOptions& options)
    : options_(options) {
  if (table.status() == QueryStatus::kInvalidInput) {
    message_ = table.message();
    return;
  }
  if (!finite_vertices(mobile)) {
    message_ = "mobile mesh has a non-finite coordinate";
    return;
  }
  status_ = table.status();
  message_.clear();
  normals_.resize(table.num_triangles());
  for (std::size_t t = 0; t < table.num_triangles(); ++t) {
    normals_[t] = table.local_normal(static_cast<std::int32_t>(t));
  }
  if (status_ == QueryStatus::kNoOverlap) return;

  const AxisFrame& frame = table.frame();
  const int threads = resolve_threads(options.num_threads);
  struct Chunk {
    std::vector<TrackedVertex> tracked;
    std::vector<double> theta;
    std::vector<std::int32_t> triangle;
  };
  std::vector<Chunk> chunks(static_cast<std::size_t>(threads));
  parallel_chunks(mobile.vertices.size(), threads,
                          [&](std::size_t begin, std::size_t end, int chunk_id) {
    Chunk& chunk = chunks[static_cast<std::size_t>(chunk_id)];
    std::vector<std::pair<std::int32_t, double>> found;
    for (std::size_t v = begin; v < end; ++v) {
      const Vec3 local = frame.to_local(mobile.vertices[v]);
      if (!table.distance_may_touch(local.norm())) continue;
      const Cylindrical cyl = to_cylindrical(local);
      circle_crossings(table, cyl.r, cyl.z, [](std::int32_t) { return true; }, found);
      if (found.empty()) continue;
      TrackedVertex tracked{static_cast<std::int32_t>(v), cyl.r, cyl.z, cyl.theta,
                            chunk.theta.size(), chunk.theta.size() + found.size()};
      for (const auto& [t, theta] : found) {
        chunk.theta.push_back(theta);
        chunk.triangle.push_back(t);
      }
      chunk.tracked.push_back(tracked);
    }
  });
  for (Chunk& chunk : chunks) {
    const std::size_t offset = crossing_theta_.size();
    for (TrackedVertex tracked : chunk.tracked) {
      tracked.first += offset;
      tracked.last += offset;
      tracked_.push_back(tracked);
    }
    crossing_theta_.insert(crossing_theta_.end(), chunk.theta.begin(), chunk.theta.end());
    crossing_triangle_.insert(crossing_triangle_.end(), chunk.triangle.begin(), chunk.triangle.end());
  }
  if (options_.pose_index) build_index();
}

std::optional<PenetrationResult> CylindricalPoseCache::trivial_answer(double angle_deg) const {
  if (status_ == QueryStatus::kInvalidInput) return invalid(message_);
  if (!std::isfinite(angle_deg)) return invalid("pose angle must be finite");
  if (status_ == QueryStatus::kNoOverlap) {
    PenetrationResult result;
    result.status = QueryStatus::kNoOverlap;
    return result;
  }
  return std::nullopt;
}

bool CylindricalPoseCache::penetration_of(const TrackedVertex& vertex, double angle_rad,
                                          PenetrationPair& pair) const {
  const double theta = wrap_angle(vertex.theta0_rad + angle_rad);
  NearestCrossing nearest;
  for (std::size_t k = vertex.first; k < vertex.last; ++k) {
    nearest.offer(theta, crossing_theta_[k], crossing_triangle_[k]);
  }
  if (arc_verdict(vertex.r, vertex.z, theta, nearest.crossing_theta_rad,
                  normals_[static_cast<std::size_t>(nearest.triangle)],
                  options_.touching_mm) != ArcVerdict::kPenetrating) {
    return false;
  }
  pair = {vertex.vertex, nearest.triangle, vertex.r * nearest.abs_delta_rad, nearest.abs_delta_rad * kDegPerRad};
  return true;
}

template <typename TrackedIndex>
PenetrationResult CylindricalPoseCache::penetrations(std::size_t count, int threads, double angle_rad,
                                                     TrackedIndex tracked_index) const {
  std::vector<std::vector<PenetrationPair>> chunks(static_cast<std::size_t>(threads));
  const auto evaluate = [&](std::size_t begin, std::size_t end, int chunk) {
    auto& out = chunks[static_cast<std::size_t>(chunk)];
    PenetrationPair pair;
    for (std::size_t k = begin; k < end; ++k) {
      if (penetration_of(tracked_[tracked_index(k)], angle_rad, pair)) out.push_back(pair);
    }
  };
  if (threads == 1) {
    evaluate(0, count, 0);
  } else {
    parallel_chunks(count, threads, evaluate);
  }
  return join_chunks(chunks);
}

PenetrationResult CylindricalPoseCache::query_every_vertex(double angle_deg) const {
  if (std::optional<PenetrationResult> answer = trivial_answer(angle_deg)) return std::move(*answer);
  return penetrations(tracked_.size(), resolve_threads(options_.num_threads), angle_deg / kDegPerRad,
                      [](std::size_t k) { return k; });
}

PenetrationResult CylindricalPoseCache::query(double angle_deg) const {
  if (std::optional<PenetrationResult> answer = trivial_answer(angle_deg)) return std::move(*answer);
  const double angle_rad = angle_deg / kDegPerRad;
  if (!options_.pose_index || !(std::abs(angle_rad) <= kIndexedAngleLimitRad)) return query_every_vertex(angle_deg);
  std::vector<std::int32_t> candidates;
  index_.stab(angle_rad, candidates);
  // Ascending tracked index = ascending mobile vertex: the output order of the full pass.
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  // Few candidates (the usual case) are not worth a hand-off to other threads.
  constexpr std::size_t kSerialCandidates = 8192;
  const int threads = candidates.size() < kSerialCandidates ? 1 : resolve_threads(options_.num_threads);
  return penetrations(candidates.size(), threads, angle_rad,
                      [&](std::size_t k) { return static_cast<std::size_t>(candidates[k]); });
}

void CylindricalPoseCache::build_index() {
  struct Crossing {
    double theta;
    CrossingSides sides;
  };
  struct Cluster {
    double lo, hi;  // crossings within kArcMarginRad of each other, one after another
    CrossingSides sides;
  };
  std::vector<AngularArc> arcs;
  std::vector<Crossing> crossings;
  std::vector<Cluster> clusters;
  for (std::size_t i = 0; i < tracked_.size(); ++i) {
    const TrackedVertex& vertex = tracked_[i];
    const auto id = static_cast<std::int32_t>(i);
    crossings.clear();
    for (std::size_t k = vertex.first; k < vertex.last; ++k) {
      crossings.push_back({crossing_theta_[k], penetrating_sides(vertex.r, vertex.z, crossing_theta_[k],
                                                                 normals_[static_cast<std::size_t>(crossing_triangle_[k])])});
    }
    std::sort(crossings.begin(), crossings.end(),
              [](const Crossing& a, const Crossing& b) { return a.theta < b.theta; });
    clusters.clear();
    for (const Crossing& crossing : crossings) {
      if (!clusters.empty() && crossing.theta - clusters.back().hi <= kArcMarginRad) {
        // Crossings this close can swap places as the nearest under rounding: either side.
        clusters.back().hi = crossing.theta;
        clusters.back().sides = {true, true};
      } else {
        clusters.push_back({crossing.theta, crossing.theta, crossing.sides});
      }
    }
    if (clusters.size() > 1 && clusters.front().lo + 2.0 * std::numbers::pi - clusters.back().hi <= kArcMarginRad) {
      clusters.front().lo = clusters.back().lo - 2.0 * std::numbers::pi;
      clusters.front().sides = {true, true};
      clusters.pop_back();
    }
    if (clusters.size() == 1) {
      // One place on the circle: the nearest crossing for every angle. Always a candidate.
      arcs.push_back({0.0, 4.0 * std::numbers::pi, id});
      continue;
    }
    // Within kArcMarginRad of a crossing every vertex's nearest crossing is as close, so the
    // touching tolerance decides it ... unless the tolerance is shorter than that arc here.
    const bool margin_beyond_touching = vertex.r * kArcMarginRad > options_.touching_mm;
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      const Cluster& a = clusters[c];
      const Cluster& b = clusters[(c + 1) % clusters.size()];
      const double b_hi = c + 1 == clusters.size() ? b.hi + 2.0 * std::numbers::pi : b.hi;
      if (a.sides.anticlockwise || b.sides.clockwise) {
        arcs.push_back({a.lo - kArcMarginRad - vertex.theta0_rad, b_hi - a.lo + 2.0 * kArcMarginRad, id});
      } else if (margin_beyond_touching) {
        arcs.push_back({a.lo - kArcMarginRad - vertex.theta0_rad, a.hi - a.lo + 2.0 * kArcMarginRad, id});
      }
    }
  }
  index_ = AngularIntervalIndex(arcs);
}

}  // namespace hipfai::contact
