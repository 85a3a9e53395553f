#include "geometry/hjc_regions.h"

#include "core/disjoint_sets.h"
#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/mesh_io.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unordered_map>

namespace hipfai::geometry {
namespace {

std::vector<double> vertex_areas(const TriMesh& mesh) {
  std::vector<double> area(mesh.num_vertices(), 0.0);
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const double a = triangle_area(mesh, t) / 3.0;
    for (const auto v : mesh.triangles[t]) area[static_cast<std::size_t>(v)] += a;
  }
  return area;
}

// Largest connected set (through triangle edges) of the vertices with keep[v].
std::vector<std::int32_t> largest_component(const TriMesh& mesh, const std::vector<char>& keep,
                                            const std::vector<double>& area) {
  const std::size_t n = mesh.num_vertices();
  DisjointSets sets(n);
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
      const auto b = static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)]);
      if (keep[a] && keep[b]) sets.unite(a, b);
    }
  }
  std::unordered_map<std::size_t, double> component_area;
  for (std::size_t v = 0; v < n; ++v) {
    if (keep[v]) component_area[sets.find(v)] += area[v];
  }
  std::size_t best = n;
  double best_area = -1.0;
  for (const auto& [root, a] : component_area) {
    if (a > best_area) { best_area = a; best = root; }
  }
  std::vector<std::int32_t> result;
  for (std::size_t v = 0; v < n; ++v) {
    if (keep[v] && sets.find(v) == best) result.push_back(static_cast<std::int32_t>(v));
  }
  return result;
}

// Vertices within `band` of the sphere whose normals make at most acos(cos_facing) with the
// radial direction (sign +1: pointing away from the centre, -1: towards it).
std::vector<char> band_mask(const TriMesh& mesh, const std::vector<Vec3>& normals, const Vec3& centre,
                            double radius, double band_low, double band_high, double cos_facing,
                            double sign) {
  std::vector<char> keep(mesh.num_vertices(), 0);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 d = mesh.vertices[v] - centre;
    const double distance = d.norm();
    if (!(distance > 0.0)) continue;
    const double e = distance - radius;
    if (e < -band_low || e > band_high) continue;
    if (sign * normals[v].dot(d) / distance < cos_facing) continue;
    keep[v] = 1;
  }
  return keep;
}

struct Refined {
  std::vector<std::int32_t> vertices;
  SphereFit sphere;
  double area = 0.0;
};

// Band -> fit -> narrower band, a few rounds, then the largest connected patch and its fit.
Refined refine(const TriMesh& mesh, const std::vector<Vec3>& normals, const std::vector<double>& area,
               Vec3 centre, double radius, double band_low, double band_high, double cos_facing,
               double sign, double min_band) {
  Refined best;
  std::vector<char> keep;
  for (int round = 0; round < 6; ++round) {
    keep = band_mask(mesh, normals, centre, radius, band_low, band_high, cos_facing, sign);
    std::vector<Vec3> points;
    for (std::size_t v = 0; v < keep.size(); ++v) if (keep[v]) points.push_back(mesh.vertices[v]);
    const SphereFit fit = fit_sphere(points);
    if (!fit.ok()) return best;
    centre = fit.center_mm;
    radius = fit.radius_mm;
    band_low = band_high = std::max(min_band, 2.5 * fit.rms_mm);
  }
  keep = band_mask(mesh, normals, centre, radius, band_low, band_high, cos_facing, sign);
  best.vertices = largest_component(mesh, keep, area);
  std::vector<Vec3> points;
  for (const auto v : best.vertices) {
    points.push_back(mesh.vertices[static_cast<std::size_t>(v)]);
    best.area += area[static_cast<std::size_t>(v)];
  }
  best.sphere = fit_sphere(points);
  return best;
}

std::vector<std::int32_t> read_integers(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw_error(path.string(), ": cannot read the region file");
  std::vector<std::int32_t> values;
  std::string token;
  std::stringstream all;
  all << in.rdbuf();
  std::string text = all.str();
  for (char& c : text) if (c == ',' || c == ';') c = ' ';
  std::istringstream tokens(text);
  while (tokens >> token) {
    char* end = nullptr;
    const long value = std::strtol(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0' || value < 0 || value > 2147483647L) {
      throw_error(path.string(), ": '", token, "' is not a vertex index or a 0/1 mask value");
    }
    values.push_back(static_cast<std::int32_t>(value));
  }
  if (values.empty()) throw_error(path.string(), ": the region file is empty");
  return values;
}

}  // namespace

TriMesh submesh_where(const TriMesh& mesh, const std::function<bool(const Vec3&)>& keep_vertex) {
  TriMesh out;
  std::vector<std::int32_t> slot(mesh.num_vertices(), -1);
  for (const Triangle& t : mesh.triangles) {
    if (!std::all_of(t.begin(), t.end(), [&](std::int32_t v) { return keep_vertex(mesh.vertices[static_cast<std::size_t>(v)]); })) {
      continue;
    }
    Triangle kept{};
    for (std::size_t k = 0; k < 3; ++k) {
      std::int32_t& s = slot[static_cast<std::size_t>(t[k])];
      if (s < 0) {
        s = static_cast<std::int32_t>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[static_cast<std::size_t>(t[k])]);
      }
      kept[k] = s;
    }
    out.triangles.push_back(kept);
  }
  return out;
}

Vec3 principal_axis(const TriMesh& mesh, Vec3* centroid) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : mesh.vertices) mean += p;
  mean /= static_cast<double>(std::max<std::size_t>(1, mesh.num_vertices()));
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : mesh.vertices) covariance += (p - mean) * (p - mean).transpose();
  if (centroid != nullptr) *centroid = mean;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(2);
}

std::vector<Vec3> vertex_normals(const TriMesh& mesh) {
  std::vector<Vec3> normals(mesh.num_vertices(), Vec3::Zero());
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 n = triangle_area_normal(mesh, t);
    for (const auto v : mesh.triangles[t]) normals[static_cast<std::size_t>(v)] += n;
  }
  for (Vec3& n : normals) {
    const double length = n.norm();
    n = length > 0.0 ? Vec3(n / length) : Vec3::Zero();
  }
  return normals;
}

SurfaceRegion region_from_vertices(const TriMesh& mesh, const std::vector<std::int32_t>& vertices,
                                   const std::string& source) {
  SurfaceRegion region;
  region.source = source;
  const std::vector<Vec3> normals = vertex_normals(mesh);
  std::vector<std::int32_t> slot(mesh.num_vertices(), -1);
  for (const auto v : vertices) {
    if (v < 0 || static_cast<std::size_t>(v) >= mesh.num_vertices()) {
      throw_error(source, ": vertex index ", v, " is out of range (", mesh.num_vertices(), " vertices)");
    }
    if (slot[static_cast<std::size_t>(v)] >= 0) continue;
    slot[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(region.patch.vertices.size());
    region.patch.vertices.push_back(mesh.vertices[static_cast<std::size_t>(v)]);
    region.normals.push_back(normals[static_cast<std::size_t>(v)]);
    region.mesh_vertices.push_back(v);
  }
  for (const Triangle& t : mesh.triangles) {
    const auto a = slot[static_cast<std::size_t>(t[0])], b = slot[static_cast<std::size_t>(t[1])],
               c = slot[static_cast<std::size_t>(t[2])];
    if (a >= 0 && b >= 0 && c >= 0) region.patch.triangles.push_back({a, b, c});
  }
  return region;
}

SurfaceRegion region_from_mesh(const TriMesh& region_mesh) {
  SurfaceRegion region;
  region.source = "mesh";
  region.patch.vertices = region_mesh.vertices;
  region.patch.triangles = region_mesh.triangles;
  region.normals = vertex_normals(region_mesh);
  region.mesh_vertices.assign(region_mesh.num_vertices(), -1);
  return region;
}

SurfaceRegion read_region(const TriMesh& mesh, const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".stl" || extension == ".obj" || extension == ".ply" || extension == ".vtp" ||
      extension == ".msh") {
    SurfaceRegion region = region_from_mesh(read_mesh(path));
    region.source = "mesh " + path.filename().string();
    return region;
  }
  const std::vector<std::int32_t> values = read_integers(path);
  const bool mask = values.size() == mesh.num_vertices() &&
                    std::all_of(values.begin(), values.end(), [](std::int32_t v) { return v <= 1; });
  std::vector<std::int32_t> vertices;
  if (mask) {
    for (std::size_t v = 0; v < values.size(); ++v) if (values[v] == 1) vertices.push_back(static_cast<std::int32_t>(v));
  } else {
    vertices = values;
  }
  SurfaceRegion region = region_from_vertices(mesh, vertices, path.string());
  region.source = (mask ? "vertex mask " : "vertex list ") + path.filename().string();
  return region;
}

SurfaceRegion find_femoral_head(const TriMesh& femur, const TriMesh* pelvis,
                                const HeadRegionOptions& options, const std::string& what) {
  const std::vector<Vec3> normals = vertex_normals(femur);
  const std::vector<double> area = vertex_areas(femur);
  // Hough vote for (centre, radius): 2 mm centre cells, 1 mm radius bins, area-weighted.
  constexpr double kCellMm = 2.0;
  const int radius_bins = static_cast<int>(std::floor(options.max_radius_mm - options.min_radius_mm)) + 1;
  const std::size_t stride = std::max<std::size_t>(1, femur.num_vertices() / 40000);
  struct Key {
    std::int64_t code;
    bool operator==(const Key& other) const { return code == other.code; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const { return std::hash<std::int64_t>()(k.code); }
  };
  auto encode = [](std::int64_t x, std::int64_t y, std::int64_t z, std::int64_t r) {
    // 17 bits per cell coordinate (+-131 m at 2 mm cells), 6 for the radius bin: 57 bits.
    return ((((x + (1 << 16)) * (1 << 17) + (y + (1 << 16))) * (1 << 17) + (z + (1 << 16))) << 6) + r;
  };
  std::unordered_map<Key, double, KeyHash> votes;
  for (std::size_t v = 0; v < femur.num_vertices(); v += stride) {
    if (normals[v].isZero()) continue;
    for (int bin = 0; bin < radius_bins; ++bin) {
      const double r = options.min_radius_mm + bin;
      const Vec3 c = femur.vertices[v] - r * normals[v];
      const auto cell = (c / kCellMm).array().floor().cast<std::int64_t>();
      votes[{encode(cell.x(), cell.y(), cell.z(), bin)}] += area[v];
    }
  }
  // Sum each cell with its 26 neighbours and the adjacent radius bins: quantisation splits votes.
  std::vector<std::pair<double, std::int64_t>> ranked;
  ranked.reserve(votes.size());
  for (const auto& [key, weight] : votes) ranked.push_back({weight, key.code});
  std::sort(ranked.begin(), ranked.end(), std::greater<>());
  if (ranked.size() > 400) ranked.resize(400);
  auto decode = [](std::int64_t code, std::int64_t& x, std::int64_t& y, std::int64_t& z, std::int64_t& r) {
    r = code & 63;
    code >>= 6;
    z = code % (1 << 17) - (1 << 16);
    code /= (1 << 17);
    y = code % (1 << 17) - (1 << 16);
    code /= (1 << 17);
    x = code - (1 << 16);
  };
  struct Candidate { double weight; Vec3 centre; double radius; };
  std::vector<Candidate> candidates;
  for (const auto& [weight, code] : ranked) {
    std::int64_t x, y, z, r;
    decode(code, x, y, z, r);
    double total = 0.0;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz)
          for (std::int64_t dr = -1; dr <= 1; ++dr) {
            if (r + dr < 0 || r + dr >= radius_bins) continue;
            const auto it = votes.find({encode(x + dx, y + dy, z + dz, r + dr)});
            if (it != votes.end()) total += it->second;
          }
    candidates.push_back({total, Vec3((x + 0.5) * kCellMm, (y + 0.5) * kCellMm, (z + 0.5) * kCellMm),
                          options.min_radius_mm + static_cast<double>(r)});
  }
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.weight > b.weight; });
  // Distinct candidates (centres 5 mm apart).
  std::vector<Candidate> distinct;
  for (const auto& c : candidates) {
    bool near = false;
    for (const auto& d : distinct) near = near || (d.centre - c.centre).norm() < 5.0;
    if (!near) distinct.push_back(c);
    if (static_cast<int>(distinct.size()) >= options.candidates) break;
  }
  const double cos_facing = std::cos(options.facing_deg * kDegToRad);
  Refined best;
  std::string rejected;
  for (const auto& c : distinct) {
    Refined r = refine(femur, normals, area, c.centre, c.radius, 2.0, 2.0, cos_facing, +1.0, options.min_band_mm);
    if (!r.sphere.ok() || r.vertices.size() < 30) continue;
    if (r.sphere.radius_mm < options.min_radius_mm || r.sphere.radius_mm > options.max_radius_mm) continue;
    if (r.sphere.rms_mm > options.max_rms_mm) continue;
    const double sphere_area = 4.0 * std::numbers::pi * r.sphere.radius_mm * r.sphere.radius_mm;
    if (r.area < options.min_coverage * sphere_area) continue;
    if (pelvis != nullptr) {
      const double reach = r.sphere.radius_mm + options.pelvis_reach_mm;
      bool near = false;
      for (const Vec3& p : pelvis->vertices) {
        if ((p - r.sphere.center_mm).squaredNorm() < reach * reach) { near = true; break; }
      }
      if (!near) continue;
    }
    if (r.area > best.area) best = std::move(r);
  }
  if (best.vertices.empty()) {
    throw_error(what, ": no femoral head found: no part of the mesh fits a sphere of radius ",
                options.min_radius_mm, "-", options.max_radius_mm, " mm",
                pelvis != nullptr ? " near the pelvis" : "");
  }
  SurfaceRegion region = region_from_vertices(femur, best.vertices, what);
  region.source = "automatic";
  region.sphere = best.sphere;
  return region;
}

SurfaceRegion find_lunate_surface(const TriMesh& pelvis, const Vec3& head_center_mm,
                                  double head_radius_mm, const LunateRegionOptions& options,
                                  const std::string& what) {
  const std::vector<Vec3> normals = vertex_normals(pelvis);
  const std::vector<double> area = vertex_areas(pelvis);
  const double cos_facing = std::cos(options.facing_deg * kDegToRad);
  std::vector<char> keep = band_mask(pelvis, normals, head_center_mm, head_radius_mm, 1.0,
                                     options.band_mm, cos_facing, -1.0);
  std::vector<Vec3> points;
  for (std::size_t v = 0; v < keep.size(); ++v) if (keep[v]) points.push_back(pelvis.vertices[v]);
  if (points.size() < options.min_vertices) {
    throw_error(what, ": no lunate surface found: ", points.size(), " vertices face the femoral head within ",
                options.band_mm, " mm of its sphere (need ", options.min_vertices, ")");
  }
  const SphereFit first = fit_sphere(points);
  if (!first.ok()) throw_error(what, ": no lunate surface found: the surface facing the head is ", to_string(first.status));
  const Refined r = refine(pelvis, normals, area, first.center_mm, first.radius_mm,
                           std::max(options.min_band_mm, 2.5 * first.rms_mm),
                           std::max(options.min_band_mm, 2.5 * first.rms_mm), cos_facing, -1.0,
                           options.min_band_mm);
  if (r.vertices.size() < options.min_vertices || !r.sphere.ok()) {
    throw_error(what, ": no lunate surface found: fewer than ", options.min_vertices,
                " vertices fit one sphere around the femoral head");
  }
  SurfaceRegion region = region_from_vertices(pelvis, r.vertices, what);
  region.source = "automatic";
  region.sphere = r.sphere;
  return region;
}

}  // namespace hipfai::geometry
