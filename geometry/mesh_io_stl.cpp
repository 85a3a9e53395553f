#include "geometry/mesh_io_stl.h"

#include "core/error.h"
#include "geometry/mesh_io_common.h"

#include <bit>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace hipfai::geometry::mesh_io {
namespace {

// Vertex welding for STL, which stores each triangle's corners separately. Only exactly equal
// coordinates merge (a tolerance would silently change the user's geometry); -0 equals +0.

struct PointKey {
  std::uint64_t bits[3];
  bool operator==(const PointKey& other) const {
    return bits[0] == other.bits[0] && bits[1] == other.bits[1] && bits[2] == other.bits[2];
  }
};

struct PointKeyHash {
  std::size_t operator()(const PointKey& key) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::uint64_t b : key.bits) {
      h ^= b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h *= 0xff51afd7ed558ccdull;
    }
    return static_cast<std::size_t>(h ^ (h >> 33));
  }
};

class VertexWelder {
 public:
  VertexWelder(TriMesh& mesh, std::size_t expected_vertices) : mesh_(mesh) {
    index_.reserve(expected_vertices);
    mesh_.vertices.reserve(expected_vertices);
  }

  std::int32_t add(const Vec3& p) {
    PointKey key{};
    for (int k = 0; k < 3; ++k) key.bits[k] = std::bit_cast<std::uint64_t>(p[k] + 0.0);
    const auto [it, inserted] =
        index_.try_emplace(key, static_cast<std::int32_t>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p);
    return it->second;
  }

 private:
  TriMesh& mesh_;
  std::unordered_map<PointKey, std::int32_t, PointKeyHash> index_;
};

bool looks_like_text(std::string_view bytes) {
  const std::size_t n = std::min<std::size_t>(bytes.size(), 1024);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if (c < 0x09 || (c > 0x0d && c < 0x20)) return false;
  }
  return true;
}

TriMesh read_binary_stl(std::string_view bytes) {
  const std::uint32_t count = load<std::uint32_t>(bytes.data() + 80, true);
  TriMesh mesh;
  // A closed surface has about half as many vertices as triangles.
  VertexWelder welder(mesh, count / 2 + 3);
  mesh.triangles.reserve(count);
  const char* record = bytes.data() + 84;
  for (std::uint32_t t = 0; t < count; ++t, record += 50) {
    Triangle tri;
    for (int corner = 0; corner < 3; ++corner) {
      const char* p = record + 12 + 12 * corner;  // skip the stored normal: we recompute it
      tri[corner] = welder.add(Vec3(load<float>(p, true), load<float>(p + 4, true),
                                    load<float>(p + 8, true)));
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

TriMesh read_ascii_stl(const std::string& name, std::string_view text) {
  TriMesh mesh;
  VertexWelder welder(mesh, text.size() / 400 + 3);  // ~ 250 bytes per facet, ~ 0.5 vertex each
  Tokenizer tokens(text);
  std::vector<std::int32_t> corners;
  auto expect = [&](std::string_view wanted) {
    const std::string_view got = tokens.next();
    if (got != wanted) {
      throw_error(name, ": line ", tokens.line(), ": expected '", wanted, "' in ASCII STL, found '",
                  got.empty() ? std::string_view("end of file") : got, "'");
    }
  };
  auto number = [&]() {
    const std::string_view token = tokens.next();
    const auto value = parse_double(token);
    if (!value) throw_error(name, ": line ", tokens.line(), ": bad number '", token, "'");
    return *value;
  };
  bool in_solid = false;
  for (;;) {
    const std::string_view word = tokens.next();
    if (word.empty()) break;
    if (word == "solid") {
      tokens.skip_line();  // the solid's name, possibly with spaces
      in_solid = true;
    } else if (word == "endsolid") {
      tokens.skip_line();
      in_solid = false;
    } else if (word == "facet" && in_solid) {
      expect("normal");
      for (int k = 0; k < 3; ++k) number();
      expect("outer");
      expect("loop");
      corners.clear();
      for (std::string_view item = tokens.next(); item != "endloop"; item = tokens.next()) {
        if (item != "vertex") {
          throw_error(name, ": line ", tokens.line(), ": expected 'vertex' or 'endloop' in ASCII STL, found '",
                      item.empty() ? std::string_view("end of file") : item, "'");
        }
        const double x = number();
        const double y = number();
        const double z = number();
        corners.push_back(welder.add(Vec3(x, y, z)));
      }
      if (corners.size() < 3) {
        throw_error(name, ": line ", tokens.line(), ": facet with ", corners.size(),
                    " vertices (at least 3 needed)");
      }
      expect("endfacet");
      add_fan(mesh, corners);
    } else {
      throw_error(name, ": line ", tokens.line(), ": unexpected '", word, "' in ASCII STL");
    }
  }
  return mesh;
}

}  // namespace

TriMesh read_stl(const std::string& name, std::string_view bytes) {
  // Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. The size test comes first
  // because many binary writers put "solid" at the start of the header.
  if (bytes.size() >= 84) {
    const std::uint64_t count = load<std::uint32_t>(bytes.data() + 80, true);
    if (84 + 50 * count == bytes.size()) return read_binary_stl(bytes);
  }
  std::size_t first = 0;
  while (first < bytes.size() && is_space(bytes[first])) ++first;
  if (bytes.substr(first, 5) == "solid" && looks_like_text(bytes)) {
    return read_ascii_stl(name, bytes);
  }
  if (bytes.size() < 84) {
    throw_error(name, ": not an STL file: ", bytes.size(),
                " bytes is too short for a binary STL and it does not start with 'solid'");
  }
  const std::uint64_t count = load<std::uint32_t>(bytes.data() + 80, true);
  const std::uint64_t whole = (bytes.size() - 84) / 50;
  if (84 + 50 * count > bytes.size()) {
    throw_error(name, ": truncated binary STL: ", whole, " of ", count, " triangles present");
  }
  throw_error(name, ": binary STL has ", bytes.size() - (84 + 50 * count),
              " bytes after its ", count, " triangles");
}

std::string write_stl(const std::string& name, const TriMesh& mesh, bool ascii) {
  std::string out;
  if (ascii) {
    out.reserve(mesh.triangles.size() * 260);
    out += "solid hipfai\n";
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Vec3 n = triangle_unit_normal(mesh, t);
      out += "  facet normal ";
      for (int k = 0; k < 3; ++k) {
        append_number(out, n[k]);
        out += k < 2 ? " " : "\n    outer loop\n";
      }
      for (const std::int32_t index : mesh.triangles[t]) {
        out += "      vertex ";
        const Vec3& p = mesh.vertices[static_cast<std::size_t>(index)];
        for (int k = 0; k < 3; ++k) {
          append_number(out, p[k]);
          out += k < 2 ? " " : "\n";
        }
      }
      out += "    endloop\n  endfacet\n";
    }
    out += "endsolid hipfai\n";
    return out;
  }
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw_error(name, ": too many triangles for binary STL");
  }
  out.reserve(84 + 50 * mesh.triangles.size());
  // The header must not start with "solid", or naive readers take the file for ASCII.
  std::string header = "binary STL written by hipfai, units mm";
  header.resize(80, ' ');
  out += header;
  store_little(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = triangle_unit_normal(mesh, t);
    for (int k = 0; k < 3; ++k) store_little(out, static_cast<float>(n[k]));
    for (const std::int32_t index : mesh.triangles[t]) {
      const Vec3& p = mesh.vertices[static_cast<std::size_t>(index)];
      for (int k = 0; k < 3; ++k) store_little(out, static_cast<float>(p[k]));
    }
    store_little(out, std::uint16_t{0});
  }
  return out;
}

}  // namespace hipfai::geometry::mesh_io
