#include "geometry/mesh_io_msh.h"

#include "core/error.h"
#include "geometry/mesh_io_common.h"

#include <limits>
#include <unordered_map>

namespace hipfai::geometry::mesh_io {
namespace {

bool known_type(std::int64_t type) {
  return (type >= 1 && type <= 7) || type == 15;
}

// Reads tokens of one file, naming the file (and the section) in every message.
class MshReader {
 public:
  MshReader(const std::string& name, std::string_view text) : name_(name), text_(text), tokens_(text) {}

  std::string_view word(const char* what) {
    const std::string_view token = tokens_.next();
    if (token.empty()) throw_error(name_, ": truncated ", what, " (the file ends early)");
    return token;
  }

  std::int64_t integer(const char* what) {
    const std::string_view token = word(what);
    const auto value = parse_int(token);
    if (!value) throw_error(name_, ": line ", tokens_.line(), ": bad integer '", token, "' in ", what);
    return *value;
  }

  double number(const char* what) {
    const std::string_view token = word(what);
    const auto value = parse_double(token);
    if (!value) throw_error(name_, ": line ", tokens_.line(), ": bad number '", token, "' in ", what);
    return *value;
  }

  void expect(std::string_view wanted) {
    const std::string_view got = tokens_.next();
    if (got != wanted) {
      throw_error(name_, ": expected ", wanted, got.empty() ? std::string(" at the end") : " but found " + std::string(got));
    }
  }

  // A count of records each at least `min_bytes` long: more than the rest of the file can hold
  // is a corrupt or truncated file, reported before anything is allocated.
  std::size_t count(const char* what, std::size_t min_bytes) {
    const std::int64_t value = integer(what);
    const std::size_t left = text_.size() - tokens_.position();
    if (value < 0 || static_cast<std::uint64_t>(value) > left / min_bytes + 1) {
      throw_error(name_, ": truncated ", what, ": ", value, " declared, the ", left,
                  " bytes left hold at most ", left / min_bytes + 1);
    }
    return static_cast<std::size_t>(value);
  }

  // The rest of the current line, trimmed.
  std::string_view rest_of_line() {
    const std::size_t begin = tokens_.position();
    tokens_.skip_line();
    std::string_view rest = text_.substr(begin, tokens_.position() - begin);
    while (!rest.empty() && is_space(rest.front())) rest.remove_prefix(1);
    while (!rest.empty() && is_space(rest.back())) rest.remove_suffix(1);
    return rest;
  }

  std::string_view next() { return tokens_.next(); }
  const std::string& name() const { return name_; }

 private:
  const std::string& name_;
  std::string_view text_;
  Tokenizer tokens_;
};

void read_nodes(MshReader& in, MshMesh& mesh, std::unordered_map<std::int64_t, std::int32_t>& index_of) {
  // "1 0 0 0\n": 8 bytes at least per node.
  const std::size_t count = in.count("$Nodes", 8);
  if (count > static_cast<std::size_t>(kMaxIndex)) throw_error(in.name(), ": ", count, " nodes exceed the 32-bit index range");
  mesh.nodes.reserve(count);
  index_of.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::int64_t id = in.integer("$Nodes");
    const double x = in.number("$Nodes");
    const double y = in.number("$Nodes");
    const double z = in.number("$Nodes");
    if (!index_of.emplace(id, static_cast<std::int32_t>(mesh.nodes.size())).second) {
      throw_error(in.name(), ": node ", id, " defined twice");
    }
    mesh.nodes.emplace_back(x, y, z);
  }
  in.expect("$EndNodes");
}

void read_elements(MshReader& in, MshMesh& mesh, const std::unordered_map<std::int64_t, std::int32_t>& index_of) {
  // "1 15 0 1\n": 8 bytes at least per element.
  const std::size_t count = in.count("$Elements", 8);
  mesh.elements.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    MshElement element;
    element.id = in.integer("$Elements");
    const std::int64_t type = in.integer("$Elements");
    if (!known_type(type)) {
      throw_error(in.name(), ": element ", element.id, " has type ", type,
                  ", which is not a first-order element this reader takes");
    }
    element.type = static_cast<MshElementType>(type);
    const std::int64_t tags = in.integer("$Elements");
    if (tags < 0) throw_error(in.name(), ": element ", element.id, " has ", tags, " tags");
    for (std::int64_t t = 0; t < tags; ++t) {
      const std::int64_t tag = in.integer("$Elements");
      if (tag < std::numeric_limits<int>::min() || tag > std::numeric_limits<int>::max()) {
        throw_error(in.name(), ": element ", element.id, " has tag ", tag, " out of range");
      }
      if (t == 0) element.physical = static_cast<int>(tag);
      if (t == 1) element.elementary = static_cast<int>(tag);
    }
    for (std::size_t k = 0; k < node_count(element.type); ++k) {
      const std::int64_t node = in.integer("$Elements");
      const auto found = index_of.find(node);
      if (found == index_of.end()) throw_error(in.name(), ": element ", element.id, " uses unknown node ", node);
      element.nodes[k] = found->second;
    }
    mesh.elements.push_back(element);
  }
  in.expect("$EndElements");
}

void read_physical_names(MshReader& in, MshMesh& mesh) {
  // "1 2 \"a\"\n": 8 bytes at least per name.
  const std::size_t count = in.count("$PhysicalNames", 8);
  for (std::size_t i = 0; i < count; ++i) {
    MshPhysicalName physical;
    physical.dimension = static_cast<int>(in.integer("$PhysicalNames"));
    physical.tag = static_cast<int>(in.integer("$PhysicalNames"));
    std::string_view text = in.rest_of_line();
    if (text.size() >= 2 && text.front() == '"' && text.back() == '"') text = text.substr(1, text.size() - 2);
    physical.name = std::string(text);
    mesh.physical_names.push_back(std::move(physical));
  }
  in.expect("$EndPhysicalNames");
}

}  // namespace

std::size_t node_count(MshElementType type) {
  switch (type) {
    case MshElementType::kPoint: return 1;
    case MshElementType::kLine: return 2;
    case MshElementType::kTriangle: return 3;
    case MshElementType::kQuadrangle:
    case MshElementType::kTetrahedron: return 4;
    case MshElementType::kPyramid: return 5;
    case MshElementType::kPrism: return 6;
    case MshElementType::kHexahedron: return 8;
  }
  return 0;
}

MshMesh parse_msh(const std::string& name, std::string_view text) {
  MshReader in(name, text);
  in.expect("$MeshFormat");
  const std::string_view version = in.next();
  const std::string_view file_type = in.next();
  in.next();  // data size: ASCII files do not depend on it
  if ((version != "2.2" && version != "2.1" && version != "2") || file_type != "0") {
    throw_error(name, ": not an ASCII MSH 2.2 file (version '", version, "', file type '", file_type,
                "'; gmsh writes it with -format msh22)");
  }
  in.expect("$EndMeshFormat");
  MshMesh mesh;
  std::unordered_map<std::int64_t, std::int32_t> index_of;
  bool have_nodes = false, have_elements = false;
  for (std::string_view section = in.next(); !section.empty(); section = in.next()) {
    if (section == "$Nodes") {
      if (have_nodes) throw_error(name, ": two $Nodes sections");
      read_nodes(in, mesh, index_of);
      have_nodes = true;
    } else if (section == "$Elements") {
      if (!have_nodes) throw_error(name, ": $Elements before $Nodes");
      if (have_elements) throw_error(name, ": two $Elements sections");
      read_elements(in, mesh, index_of);
      have_elements = true;
    } else if (section == "$PhysicalNames") {
      read_physical_names(in, mesh);
    } else if (section.front() == '$') {
      // Another section ($NodeData, $Periodic, ...): skip to its end marker.
      const std::string end = "$End" + std::string(section.substr(1));
      std::string_view token = in.next();
      while (!token.empty() && token != end) token = in.next();
      if (token.empty()) throw_error(name, ": unterminated section ", section);
    } else {
      throw_error(name, ": unexpected '", section, "' between sections");
    }
  }
  if (!have_elements) throw_error(name, ": no $Elements section");
  return mesh;
}

std::string format_msh(const MshMesh& mesh) {
  std::string out = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  if (!mesh.physical_names.empty()) {
    out += "$PhysicalNames\n" + std::to_string(mesh.physical_names.size()) + "\n";
    for (const MshPhysicalName& physical : mesh.physical_names) {
      out += std::to_string(physical.dimension) + " " + std::to_string(physical.tag) + " \"" + physical.name + "\"\n";
    }
    out += "$EndPhysicalNames\n";
  }
  out += "$Nodes\n" + std::to_string(mesh.nodes.size()) + "\n";
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    append_number(out, static_cast<std::int64_t>(i + 1));
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, mesh.nodes[i][k]);
    }
    out += '\n';
  }
  out += "$EndNodes\n$Elements\n" + std::to_string(mesh.elements.size()) + "\n";
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const MshElement& element = mesh.elements[i];
    // id type tag-count physical elementary nodes...
    out += std::to_string(i + 1) + " " + std::to_string(static_cast<int>(element.type)) + " 2 " +
           std::to_string(element.physical) + " " + std::to_string(element.elementary);
    for (std::size_t k = 0; k < node_count(element.type); ++k) {
      out += ' ';
      append_number(out, static_cast<std::int64_t>(element.nodes[k]) + 1);
    }
    out += '\n';
  }
  out += "$EndElements\n";
  return out;
}

TriMesh read_msh(const std::string& name, std::string_view text) {
  const MshMesh msh = parse_msh(name, text);
  auto is_surface = [](const MshElement& element) {
    return element.type == MshElementType::kTriangle || element.type == MshElementType::kQuadrangle;
  };
  // Only the nodes the surface uses (a file may also hold points, lines and volume elements'
  // interior nodes), in file order, so a file we wrote reads back with the same numbering.
  std::vector<std::int32_t> vertex_of(msh.nodes.size(), -1);
  for (const MshElement& element : msh.elements) {
    if (!is_surface(element)) continue;
    for (std::size_t k = 0; k < node_count(element.type); ++k) vertex_of[static_cast<std::size_t>(element.nodes[k])] = 0;
  }
  TriMesh mesh;
  for (std::size_t node = 0; node < msh.nodes.size(); ++node) {
    if (vertex_of[node] < 0) continue;
    vertex_of[node] = static_cast<std::int32_t>(mesh.vertices.size());
    mesh.vertices.push_back(msh.nodes[node]);
  }
  auto vertex = [&](std::int32_t node) { return vertex_of[static_cast<std::size_t>(node)]; };
  for (const MshElement& element : msh.elements) {
    const auto& n = element.nodes;
    if (element.type == MshElementType::kTriangle) {
      mesh.triangles.push_back({vertex(n[0]), vertex(n[1]), vertex(n[2])});
    } else if (element.type == MshElementType::kQuadrangle) {
      mesh.triangles.push_back({vertex(n[0]), vertex(n[1]), vertex(n[2])});
      mesh.triangles.push_back({vertex(n[0]), vertex(n[2]), vertex(n[3])});
    }
  }
  return mesh;
}

std::string write_msh(const TriMesh& mesh) {
  MshMesh msh;
  msh.nodes = mesh.vertices;
  msh.elements.reserve(mesh.triangles.size());
  for (const Triangle& triangle : mesh.triangles) {
    MshElement element;
    element.type = MshElementType::kTriangle;
    element.physical = 1;
    element.elementary = 1;
    for (int k = 0; k < 3; ++k) element.nodes[static_cast<std::size_t>(k)] = triangle[static_cast<std::size_t>(k)];
    msh.elements.push_back(element);
  }
  return format_msh(msh);
}

}  // namespace hipfai::geometry::mesh_io
