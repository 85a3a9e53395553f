#include "geometry/planar_quad_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <utility>

namespace hipfai::geometry {
namespace {

using Quad = std::array<std::int32_t, 4>;

std::size_t at(std::int32_t v) { return static_cast<std::size_t>(v); }

// The angle at `corner` from the edge towards `next` counter-clockwise to the edge towards
// `previous`, in [0, 2 pi).
double corner_angle(const Eigen::Vector2d& corner, const Eigen::Vector2d& next, const Eigen::Vector2d& previous) {
  const Eigen::Vector2d u = next - corner;
  const Eigen::Vector2d w = previous - corner;
  const double angle = std::atan2(u.x() * w.y() - u.y() * w.x(), u.dot(w));
  return angle < 0.0 ? angle + 2.0 * std::numbers::pi : angle;
}

// Sine of the corner at c (the cross product over the edge lengths): positive for a convex
// corner of a counter-clockwise quad, -1 for a degenerate one.
double corner_sine(const PlanarQuadMesh& mesh, const Quad& quad, std::size_t c) {
  const Eigen::Vector2d& p = mesh.nodes[at(quad[c])];
  const Eigen::Vector2d u = mesh.nodes[at(quad[(c + 1) % 4])] - p;
  const Eigen::Vector2d w = mesh.nodes[at(quad[(c + 3) % 4])] - p;
  const double lengths = u.norm() * w.norm();
  return lengths > 0.0 ? (u.x() * w.y() - u.y() * w.x()) / lengths : -1.0;
}

double smallest_sine(const PlanarQuadMesh& mesh, const Quad& quad) {
  double lowest = 1.0;
  for (std::size_t c = 0; c < 4; ++c) lowest = std::min(lowest, corner_sine(mesh, quad, c));
  return lowest;
}

// `quad` turned so that `node` is its corner 0.
Quad starting_at(const Quad& quad, std::int32_t node) {
  const auto c = static_cast<std::size_t>(std::find(quad.begin(), quad.end(), node) - quad.begin());
  return {quad[c], quad[(c + 1) % 4], quad[(c + 2) % 4], quad[(c + 3) % 4]};
}

std::pair<std::int32_t, std::int32_t> edge_key(std::int32_t a, std::int32_t b) { return {std::min(a, b), std::max(a, b)}; }

struct Topology {
  std::vector<int> uses;                                                   // quads per node
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::size_t>> quads_of_edge;

  explicit Topology(const PlanarQuadMesh& mesh) : uses(mesh.nodes.size(), 0) {
    for (std::size_t q = 0; q < mesh.quads.size(); ++q) {
      for (std::size_t c = 0; c < 4; ++c) {
        ++uses[at(mesh.quads[q][c])];
        quads_of_edge[edge_key(mesh.quads[q][c], mesh.quads[q][(c + 1) % 4])].push_back(q);
      }
    }
  }
  std::optional<std::size_t> across(std::int32_t a, std::int32_t b, std::size_t from) const {
    const auto found = quads_of_edge.find(edge_key(a, b));
    if (found == quads_of_edge.end() || found->second.size() != 2) return std::nullopt;
    return found->second[0] == from ? found->second[1] : found->second[0];
  }
};

bool flat_single_corner(const PlanarQuadMesh& mesh, const Topology& topology, const Quad& quad, std::size_t c,
                        double max_corner_rad) {
  const std::int32_t node = quad[c];
  return mesh.on_boundary[at(node)] && topology.uses[at(node)] == 1 && quad_corner_angle(mesh, quad, c) > max_corner_rad;
}

// One possible swap: the two quads replacing q and its neighbour, and the quality they reach.
struct Swap {
  std::size_t neighbour = 0;
  Quad first{}, second{};
  double quality = -2.0;
};

// The swap of q = (v, n, o, p) with its neighbour across the edge (a, b) = (n, o) or (o, p);
// `losers`: the two nodes that end in one quad fewer.
std::optional<Swap> try_swap(const PlanarQuadMesh& mesh, const Topology& topology, std::size_t q, const Quad& around_v,
                             bool across_n_o, double max_corner_rad) {
  const auto [v, n, o, p] = around_v;
  const std::int32_t a = across_n_o ? n : o;
  const std::int32_t b = across_n_o ? o : p;
  const auto neighbour = topology.across(a, b, q);
  if (!neighbour) return std::nullopt;
  // The neighbour runs b -> a; its other two corners follow a.
  const Quad other = starting_at(mesh.quads[*neighbour], b);
  if (other[1] != a) return std::nullopt;  // not a consistently oriented pair
  Swap swap;
  swap.neighbour = *neighbour;
  // Hexagon v, n, ..., p counter-clockwise, split by the diagonal from v to its opposite corner.
  if (across_n_o) {
    // other = (o, n, x, y): hexagon v n x y o p, diagonal v-y.
    swap.first = {v, n, other[2], other[3]};
    swap.second = {other[3], o, p, v};
  } else {
    // other = (p, o, s, t): hexagon v n o s t p, diagonal v-s.
    swap.first = {v, n, o, other[2]};
    swap.second = {other[2], other[3], p, v};
  }
  swap.quality = std::min(smallest_sine(mesh, swap.first), smallest_sine(mesh, swap.second));
  const double before = std::min(smallest_sine(mesh, mesh.quads[q]), smallest_sine(mesh, mesh.quads[*neighbour]));
  if (swap.quality <= 0.0 || swap.quality <= before) return std::nullopt;
  // The two nodes of the shared edge lose a quad.
  for (const std::int32_t loser : {a, b}) {
    const int left = topology.uses[at(loser)] - 1;
    if (!mesh.on_boundary[at(loser)] && left < 3) return std::nullopt;
    if (mesh.on_boundary[at(loser)] && left == 1) {
      const Quad& kept = std::find(swap.first.begin(), swap.first.end(), loser) != swap.first.end() ? swap.first : swap.second;
      const auto c = static_cast<std::size_t>(std::find(kept.begin(), kept.end(), loser) - kept.begin());
      if (quad_corner_angle(mesh, kept, c) > max_corner_rad) return std::nullopt;
    }
  }
  return swap;
}

// One swap at the first flat single corner that has one; false when none has.
bool open_one(PlanarQuadMesh& mesh, double max_corner_rad, std::size_t& found) {
  const Topology topology(mesh);
  found = 0;
  std::optional<std::pair<std::size_t, Swap>> chosen;
  for (std::size_t q = 0; q < mesh.quads.size(); ++q) {
    for (std::size_t c = 0; c < 4; ++c) {
      if (!flat_single_corner(mesh, topology, mesh.quads[q], c, max_corner_rad)) continue;
      ++found;
      if (chosen) continue;
      const Quad around_v = starting_at(mesh.quads[q], mesh.quads[q][c]);
      std::optional<Swap> best;
      for (const bool across_n_o : {true, false}) {
        auto swap = try_swap(mesh, topology, q, around_v, across_n_o, max_corner_rad);
        if (swap && (!best || swap->quality > best->quality)) best = swap;
      }
      if (best) chosen.emplace(q, *best);
    }
  }
  if (!chosen) return false;
  mesh.quads[chosen->first] = chosen->second.first;
  mesh.quads[chosen->second.neighbour] = chosen->second.second;
  return true;
}

// --- triangles ------------------------------------------------------------------------------

using Triangle3 = std::array<std::int32_t, 3>;

double triangle_angle(const PlanarTriMesh& mesh, const Triangle3& t, std::size_t c) {
  return corner_angle(mesh.nodes[at(t[c])], mesh.nodes[at(t[(c + 1) % 3])], mesh.nodes[at(t[(c + 2) % 3])]);
}

double twice_area(const PlanarTriMesh& mesh, const Triangle3& t) {
  const Eigen::Vector2d u = mesh.nodes[at(t[1])] - mesh.nodes[at(t[0])];
  const Eigen::Vector2d w = mesh.nodes[at(t[2])] - mesh.nodes[at(t[0])];
  return u.x() * w.y() - u.y() * w.x();
}

// Smallest angle of a counter-clockwise triangle; -1 when it is not counter-clockwise.
double smallest_angle(const PlanarTriMesh& mesh, const Triangle3& t) {
  if (twice_area(mesh, t) <= 0.0) return -1.0;
  return std::min({triangle_angle(mesh, t, 0), triangle_angle(mesh, t, 1), triangle_angle(mesh, t, 2)});
}

// One flip at the first ear that has one; false when none has.
bool flip_one(PlanarTriMesh& mesh, double max_corner_rad, std::size_t& found) {
  std::vector<int> uses(mesh.nodes.size(), 0);
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::size_t>> triangles_of_edge;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      ++uses[at(mesh.triangles[t][c])];
      triangles_of_edge[edge_key(mesh.triangles[t][c], mesh.triangles[t][(c + 1) % 3])].push_back(t);
    }
  }
  const auto is_ear = [&](const Triangle3& t, std::size_t c, const std::vector<int>& count) {
    return mesh.on_boundary[at(t[c])] && count[at(t[c])] == 1 && triangle_angle(mesh, t, c) > max_corner_rad;
  };
  found = 0;
  bool flipped = false;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      if (!is_ear(mesh.triangles[t], c, uses)) continue;
      ++found;
      if (flipped) continue;
      const Triangle3& ear = mesh.triangles[t];
      const std::int32_t v = ear[c], a = ear[(c + 1) % 3], b = ear[(c + 2) % 3];
      const auto& sharing = triangles_of_edge[edge_key(a, b)];
      if (sharing.size() != 2) continue;
      const std::size_t other = sharing[0] == t ? sharing[1] : sharing[0];
      // The triangle across runs b -> a -> w.
      const Triangle3& across = mesh.triangles[other];
      std::int32_t w = -1;
      for (std::int32_t node : across) {
        if (node != a && node != b) w = node;
      }
      if (w < 0) continue;  // a degenerate triangle across: nothing to flip to
      const Triangle3 first{v, a, w}, second{v, w, b};
      const double before = std::min(smallest_angle(mesh, ear), smallest_angle(mesh, across));
      const double after = std::min(smallest_angle(mesh, first), smallest_angle(mesh, second));
      if (after <= 0.0 || after <= before) continue;
      std::vector<int> count = uses;
      --count[at(a)];
      --count[at(b)];
      ++count[at(v)];
      ++count[at(w)];
      bool acceptable = true;
      for (const auto& [node, kept] : {std::pair{a, first}, std::pair{b, second}}) {
        if (!mesh.on_boundary[at(node)] && count[at(node)] < 3) acceptable = false;
        const auto k = static_cast<std::size_t>(std::find(kept.begin(), kept.end(), node) - kept.begin());
        if (is_ear(kept, k, count)) acceptable = false;
      }
      if (!acceptable) continue;
      mesh.triangles[t] = first;
      mesh.triangles[other] = second;
      flipped = true;
    }
  }
  return flipped;
}

// Repairs one at a time (`step(bound_rad, found)`: one repair, the count of candidates before it)
// until a step makes none; `found` counts the candidates of the first step.
template <typename Step>
FlatCornerRepair repeat_until_done(double max_corner_deg, Step step) {
  const double max_corner_rad = max_corner_deg * std::numbers::pi / 180.0;
  FlatCornerRepair repair;
  std::size_t found = 0;
  for (bool first = true;; first = false) {
    const bool repaired = step(max_corner_rad, found);
    if (first) repair.found = found;
    if (!repaired) break;
    ++repair.opened;
  }
  return repair;
}

}  // namespace

FlatCornerRepair flip_flat_boundary_ears(PlanarTriMesh& mesh, double max_corner_deg) {
  // Every flip removes one ear and makes none, so this ends.
  return repeat_until_done(max_corner_deg, [&](double bound, std::size_t& found) { return flip_one(mesh, bound, found); });
}

PlanarQuadMesh split_into_quads(const PlanarTriMesh& mesh, int sweeps) {
  PlanarQuadMesh result;
  result.nodes = mesh.nodes;
  result.on_boundary = mesh.on_boundary;
  std::map<std::pair<std::int32_t, std::int32_t>, int> edge_uses;
  for (const auto& t : mesh.triangles) {
    for (std::size_t c = 0; c < 3; ++c) ++edge_uses[edge_key(t[c], t[(c + 1) % 3])];
  }
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoint_of;
  const auto midpoint = [&](std::int32_t a, std::int32_t b) {
    const auto key = edge_key(a, b);
    const auto found = midpoint_of.find(key);
    if (found != midpoint_of.end()) return found->second;
    const auto index = static_cast<std::int32_t>(result.nodes.size());
    result.nodes.push_back(0.5 * (mesh.nodes[at(a)] + mesh.nodes[at(b)]));
    result.on_boundary.push_back(edge_uses[key] == 1);
    midpoint_of.emplace(key, index);
    return index;
  };
  for (const auto& t : mesh.triangles) {
    const std::array<std::int32_t, 3> middle{midpoint(t[0], t[1]), midpoint(t[1], t[2]), midpoint(t[2], t[0])};
    const auto centre = static_cast<std::int32_t>(result.nodes.size());
    result.nodes.push_back((mesh.nodes[at(t[0])] + mesh.nodes[at(t[1])] + mesh.nodes[at(t[2])]) / 3.0);
    result.on_boundary.push_back(false);
    for (std::size_t c = 0; c < 3; ++c) result.quads.push_back({t[c], middle[c], centre, middle[(c + 2) % 3]});
  }
  std::vector<std::set<std::int32_t>> neighbours(result.nodes.size());
  for (const auto& quad : result.quads) {
    for (std::size_t c = 0; c < 4; ++c) {
      neighbours[at(quad[c])].insert(quad[(c + 1) % 4]);
      neighbours[at(quad[c])].insert(quad[(c + 3) % 4]);
    }
  }
  double quality = planar_quality(result);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    std::vector<Eigen::Vector2d> moved = result.nodes;
    for (std::size_t v = 0; v < moved.size(); ++v) {
      if (result.on_boundary[v] || neighbours[v].empty()) continue;
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for (std::int32_t u : neighbours[v]) mean += result.nodes[at(u)];
      moved[v] = mean / static_cast<double>(neighbours[v].size());
    }
    std::swap(moved, result.nodes);
    const double smoothed = planar_quality(result);
    if (smoothed < quality) {
      std::swap(moved, result.nodes);
      break;
    }
    quality = smoothed;
  }
  return result;
}

double quad_corner_angle(const PlanarQuadMesh& mesh, const Quad& quad, std::size_t c) {
  return corner_angle(mesh.nodes[at(quad[c])], mesh.nodes[at(quad[(c + 1) % 4])], mesh.nodes[at(quad[(c + 3) % 4])]);
}

double planar_quality(const PlanarQuadMesh& mesh) {
  double lowest = 1.0;
  for (const auto& quad : mesh.quads) lowest = std::min(lowest, smallest_sine(mesh, quad));
  return lowest;
}

FlatCornerRepair open_flat_boundary_corners(PlanarQuadMesh& mesh, double max_corner_deg) {
  // Every swap removes one flat single corner and makes none, so this ends.
  return repeat_until_done(max_corner_deg, [&](double bound, std::size_t& found) { return open_one(mesh, bound, found); });
}

}  // namespace hipfai::geometry
