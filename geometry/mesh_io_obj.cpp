#include "geometry/mesh_io_obj.h"

#include "core/error.h"
#include "geometry/mesh_io_common.h"

#include <cstdint>
#include <vector>

namespace hipfai::geometry::mesh_io {

TriMesh read_obj(const std::string& name, std::string_view text) {
  TriMesh mesh;
  mesh.vertices.reserve(text.size() / 80);
  mesh.triangles.reserve(text.size() / 40);
  std::vector<std::int32_t> corners;
  std::size_t line_number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    Tokenizer tokens(line);
    const std::string_view keyword = tokens.next();
    if (keyword == "v") {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        const std::string_view token = tokens.next();
        if (token.empty()) throw_error(name, ": line ", line_number, ": vertex needs 3 coordinates");
        const auto value = parse_double(token);
        if (!value) throw_error(name, ": line ", line_number, ": bad number '", token, "'");
        p[k] = *value;
      }
      mesh.vertices.push_back(p);  // a 4th (w) or colour values are ignored
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view item = tokens.next(); !item.empty(); item = tokens.next()) {
        const std::string_view index_text = item.substr(0, item.find('/'));
        const auto index = parse_int(index_text);
        if (!index) throw_error(name, ": line ", line_number, ": bad face index '", item, "'");
        const auto count = static_cast<std::int64_t>(mesh.vertices.size());
        // OBJ counts from 1; negative indices count back from the latest vertex.
        std::int64_t zero_based = 0;
        if (*index > 0) {
          zero_based = *index - 1;
        } else if (*index < 0) {
          zero_based = count + *index;
          if (zero_based < 0) {
            throw_error(name, ": line ", line_number, ": relative face index ", *index,
                        " reaches before the first vertex (", count, " defined so far)");
          }
        } else {
          throw_error(name, ": line ", line_number, ": face index 0 (OBJ indices start at 1)");
        }
        if (zero_based > kMaxIndex) {
          throw_error(name, ": line ", line_number, ": face index ", *index, " out of range");
        }
        corners.push_back(static_cast<std::int32_t>(zero_based));
      }
      if (corners.size() < 3) {
        throw_error(name, ": line ", line_number, ": face with ", corners.size(),
                    " vertices (at least 3 needed)");
      }
      add_fan(mesh, corners);
    }
    // Everything else (comments, vt, vn, g, o, s, usemtl, mtllib, l, p) carries nothing we use.
  }
  return mesh;
}

std::string write_obj(const TriMesh& mesh) {
  std::string out;
  out.reserve(mesh.vertices.size() * 60 + mesh.triangles.size() * 30);
  out += "# written by hipfai, units mm\n";
  for (const Vec3& p : mesh.vertices) {
    out += "v ";
    for (int k = 0; k < 3; ++k) {
      append_number(out, p[k]);
      out += k < 2 ? " " : "\n";
    }
  }
  for (const Triangle& tri : mesh.triangles) {
    out += "f ";
    for (int k = 0; k < 3; ++k) {
      append_number(out, static_cast<std::int64_t>(tri[k]) + 1);
      out += k < 2 ? " " : "\n";
    }
  }
  return out;
}

}  // namespace hipfai::geometry::mesh_io
