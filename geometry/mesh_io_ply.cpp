#include "geometry/mesh_io_ply.h"

#include "core/error.h"
#include "geometry/mesh_io_common.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace hipfai::geometry::mesh_io {
namespace {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::optional<PlyType> ply_type(std::string_view word) {
  static const std::pair<std::string_view, PlyType> names[] = {
      {"char", PlyType::int8},     {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
      {"uint8", PlyType::uint8},   {"short", PlyType::int16},     {"int16", PlyType::int16},
      {"ushort", PlyType::uint16}, {"uint16", PlyType::uint16},   {"int", PlyType::int32},
      {"int32", PlyType::int32},   {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
      {"float", PlyType::float32}, {"float32", PlyType::float32}, {"double", PlyType::float64},
      {"float64", PlyType::float64}};
  for (const auto& [text, type] : names) {
    if (text == word) return type;
  }
  return std::nullopt;
}

std::size_t ply_size(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8: return 1;
    case PlyType::int16:
    case PlyType::uint16: return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32: return 4;
    case PlyType::float64: return 8;
  }
  return 0;
}

bool ply_is_integer(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;
  bool is_list = false;
  PlyType count_type = PlyType::uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

// Reads values of one element record, either from binary memory or from text tokens.
class PlyValueReader {
 public:
  PlyValueReader(const std::string& name, std::string_view body, PlyFormat format)
      : name_(name), body_(body), format_(format), tokens_(body) {}

  // Sets the element being read, for messages.
  void at(const PlyElement& element, std::uint64_t index) {
    element_ = &element;
    index_ = index;
  }

  double value(PlyType type) {
    if (format_ == PlyFormat::ascii) {
      const std::string_view token = next_token();
      const auto parsed = parse_double(token);
      if (!parsed) fail("bad number '", token, "'");
      return *parsed;
    }
    const char* p = take(ply_size(type));
    const bool little = format_ == PlyFormat::binary_little_endian;
    switch (type) {
      case PlyType::int8: return static_cast<std::int8_t>(*p);
      case PlyType::uint8: return static_cast<std::uint8_t>(*p);
      case PlyType::int16: return load<std::int16_t>(p, little);
      case PlyType::uint16: return load<std::uint16_t>(p, little);
      case PlyType::int32: return load<std::int32_t>(p, little);
      case PlyType::uint32: return load<std::uint32_t>(p, little);
      case PlyType::float32: return load<float>(p, little);
      case PlyType::float64: return load<double>(p, little);
    }
    return 0.0;
  }

  std::int64_t integer(PlyType type) {
    if (format_ == PlyFormat::ascii) {
      const std::string_view token = next_token();
      const auto parsed = parse_int(token);
      if (!parsed) fail("bad integer '", token, "'");
      return *parsed;
    }
    // Integer types only (checked at header time); all of them fit in a double exactly.
    return static_cast<std::int64_t>(value(type));
  }

  template <typename... Parts>
  [[noreturn]] void fail(Parts&&... parts) const {
    throw_error(name_, ": ", element_->name, " ", index_, ": ", std::forward<Parts>(parts)...);
  }

 private:
  std::string_view next_token() {
    const std::string_view token = tokens_.next();
    if (token.empty()) {
      throw_error(name_, ": PLY body ends early in ", element_->name, " ", index_, " of ",
                  element_->count);
    }
    return token;
  }

  const char* take(std::size_t bytes) {
    if (body_.size() - offset_ < bytes) {
      throw_error(name_, ": PLY body ends early in ", element_->name, " ", index_, " of ",
                  element_->count);
    }
    const char* p = body_.data() + offset_;
    offset_ += bytes;
    return p;
  }

  const std::string& name_;
  std::string_view body_;
  PlyFormat format_;
  Tokenizer tokens_;
  std::size_t offset_ = 0;
  const PlyElement* element_ = nullptr;
  std::uint64_t index_ = 0;
};

// One header statement (a line's tokens after its keyword) into the format or the elements.
void read_header_line(const std::string& name, std::size_t line_number, std::string_view keyword, Tokenizer& tokens,
                      std::optional<PlyFormat>& format, std::vector<PlyElement>& elements) {
  auto fail = [&](auto&&... parts) {
    throw_error(name, ": PLY header line ", line_number, ": ", parts...);
  };
  if (keyword == "format") {
    const std::string_view kind = tokens.next();
    if (kind == "ascii") {
      format = PlyFormat::ascii;
    } else if (kind == "binary_little_endian") {
      format = PlyFormat::binary_little_endian;
    } else if (kind == "binary_big_endian") {
      format = PlyFormat::binary_big_endian;
    } else {
      fail("unknown format '", kind, "'");
    }
  } else if (keyword == "element") {
    PlyElement element;
    element.name = std::string(tokens.next());
    const std::string_view count_text = tokens.next();
    const auto count = parse_int(count_text);
    if (element.name.empty() || !count || *count < 0) {
      fail("bad element count '", count_text, "'");
    }
    element.count = static_cast<std::uint64_t>(*count);
    elements.push_back(std::move(element));
  } else if (keyword == "property") {
    if (elements.empty()) fail("property before any element");
    PlyProperty property;
    std::string_view type_word = tokens.next();
    if (type_word == "list") {
      property.is_list = true;
      const std::string_view count_word = tokens.next();
      const auto count_type = ply_type(count_word);
      if (!count_type || !ply_is_integer(*count_type)) {
        fail("list count type '", count_word, "' is not an integer type");
      }
      property.count_type = *count_type;
      type_word = tokens.next();
    }
    const auto type = ply_type(type_word);
    if (!type) fail("unknown property type '", type_word, "'");
    property.type = *type;
    property.name = std::string(tokens.next());
    if (property.name.empty()) fail("property without a name");
    elements.back().properties.push_back(std::move(property));
  } else {
    fail("unknown keyword '", keyword, "'");
  }
}

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::size_t body_start = 0;  // the body's first byte in the file
};

// The header, one statement per line, up to end_header.
PlyHeader read_ply_header(const std::string& name, std::string_view bytes) {
  if (bytes.substr(0, 3) != "ply" || bytes.size() < 4 || (bytes[3] != '\n' && bytes[3] != '\r')) {
    throw_error(name, ": not a PLY file (does not start with 'ply')");
  }
  const std::size_t header_end = bytes.find("end_header");
  if (header_end == std::string_view::npos) throw_error(name, ": PLY header has no end_header");
  PlyHeader out;
  out.body_start = header_end + 10;
  if (out.body_start < bytes.size() && bytes[out.body_start] == '\r') ++out.body_start;
  if (out.body_start < bytes.size() && bytes[out.body_start] == '\n') ++out.body_start;
  std::optional<PlyFormat> format;
  const std::string_view header = bytes.substr(0, header_end);
  std::size_t pos = 0;
  std::size_t line_number = 0;
  while (pos < header.size()) {
    std::size_t end = header.find('\n', pos);
    if (end == std::string_view::npos) end = header.size();
    Tokenizer tokens(header.substr(pos, end - pos));
    pos = end + 1;
    ++line_number;
    const std::string_view keyword = tokens.next();
    if (keyword.empty() || keyword == "ply" || keyword == "comment" || keyword == "obj_info") continue;
    read_header_line(name, line_number, keyword, tokens, format, out.elements);
  }
  if (!format) throw_error(name, ": PLY header has no format line");
  out.format = *format;
  return out;
}

// Guard every allocation against counts the body cannot hold: each binary record needs at least
// its fixed bytes, each text record at least one character and a separator per value.
void check_counts(const std::string& name, const PlyHeader& header, std::string_view body) {
  std::uint64_t needed = 0;
  for (const PlyElement& element : header.elements) {
    // Records without properties take no bytes, so no body size bounds their count (fuzzing found
    // a header declaring 1.8e11 of them: minutes of empty loop or an allocation per record).
    if (element.properties.empty() && element.count > 0) {
      throw_error(name, ": PLY element '", element.name, "' declares ", element.count, " records but no properties");
    }
    std::uint64_t record = 0;
    for (const PlyProperty& property : element.properties) {
      if (header.format == PlyFormat::ascii) {
        record += 2;
      } else {
        record += ply_size(property.is_list ? property.count_type : property.type);
      }
    }
    if (record > 0 && element.count > (body.size() + 1) / record) {
      throw_error(name, ": PLY header declares ", element.count, " ", element.name,
                  " elements but the body holds only ", body.size(), " bytes");
    }
    needed += element.count * record;
    if (needed > body.size() + 1) {
      throw_error(name, ": PLY header declares more data than the ", body.size(),
                  "-byte body holds");
    }
  }
}

// The vertex element: positions from x, y, z, every other scalar property a vertex field.
void read_vertices(const std::string& name, const PlyElement& element, PlyValueReader& reader, TriMesh& mesh) {
  if (element.count > static_cast<std::uint64_t>(kMaxIndex)) {
    throw_error(name, ": ", element.count, " vertices exceed the 32-bit index range");
  }
  // Which slot each property fills: 0..2 position, 3 + k field k, -1 a skipped list.
  std::vector<int> slot;
  std::vector<std::vector<double>*> fields;
  bool has[3] = {false, false, false};
  for (const PlyProperty& property : element.properties) {
    const int axis = property.name == "x" ? 0 : property.name == "y" ? 1 : property.name == "z" ? 2 : -1;
    if (property.is_list) {
      slot.push_back(-1);
    } else if (axis >= 0) {
      slot.push_back(axis);
      has[axis] = true;
    } else {
      slot.push_back(3 + static_cast<int>(fields.size()));
      std::vector<double>& field = mesh.vertex_fields[property.name];
      field.reserve(element.count);
      fields.push_back(&field);
    }
  }
  if (!has[0] || !has[1] || !has[2]) {
    throw_error(name, ": PLY vertex element lacks an x, y or z property");
  }
  mesh.vertices.resize(element.count);
  for (std::uint64_t v = 0; v < element.count; ++v) {
    reader.at(element, v);
    Vec3& p = mesh.vertices[v];
    for (std::size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& property = element.properties[k];
      if (property.is_list) {
        const std::int64_t n = reader.integer(property.count_type);
        if (n < 0) reader.fail("negative list length ", n);
        for (std::int64_t i = 0; i < n; ++i) reader.value(property.type);
        continue;
      }
      const double value = reader.value(property.type);
      if (slot[k] < 3) {
        p[slot[k]] = value;
      } else {
        fields[static_cast<std::size_t>(slot[k] - 3)]->push_back(value);
      }
    }
  }
}

// The face element: each vertex_indices (or vertex_index) polygon as a fan of triangles.
void read_faces(const std::string& name, const PlyElement& element, PlyValueReader& reader, TriMesh& mesh) {
  const auto index_property =
      std::find_if(element.properties.begin(), element.properties.end(), [](const PlyProperty& p) {
        return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
      });
  if (index_property == element.properties.end()) {
    throw_error(name, ": PLY face element has no vertex_indices list");
  }
  if (!ply_is_integer(index_property->type)) {
    throw_error(name, ": PLY vertex_indices has a non-integer type");
  }
  const auto vertex_count = static_cast<std::int64_t>(mesh.vertices.size());
  mesh.triangles.reserve(element.count);
  std::vector<std::int32_t> corners;
  for (std::uint64_t f = 0; f < element.count; ++f) {
    reader.at(element, f);
    for (const PlyProperty& property : element.properties) {
      if (!property.is_list) {
        reader.value(property.type);
        continue;
      }
      const std::int64_t n = reader.integer(property.count_type);
      if (n < 0) reader.fail("negative list length ", n);
      if (&property != &*index_property) {
        for (std::int64_t i = 0; i < n; ++i) reader.value(property.type);
        continue;
      }
      if (n < 3) reader.fail("face with ", n, " vertices (at least 3 needed)");
      corners.clear();
      for (std::int64_t i = 0; i < n; ++i) {
        const std::int64_t index = reader.integer(property.type);
        if (index < 0 || index >= vertex_count) {
          reader.fail("vertex index ", index, " out of range (", vertex_count, " vertices)");
        }
        corners.push_back(static_cast<std::int32_t>(index));
      }
      add_fan(mesh, corners);
    }
  }
}

// Edges, materials, ...: read past them.
void skip_element(const PlyElement& element, PlyValueReader& reader) {
  for (std::uint64_t e = 0; e < element.count; ++e) {
    reader.at(element, e);
    for (const PlyProperty& property : element.properties) {
      const std::int64_t n = property.is_list ? reader.integer(property.count_type) : 1;
      if (n < 0) reader.fail("negative list length ", n);
      for (std::int64_t i = 0; i < n; ++i) reader.value(property.type);
    }
  }
}

}  // namespace

TriMesh read_ply(const std::string& name, std::string_view bytes) {
  const PlyHeader header = read_ply_header(name, bytes);
  const std::string_view body = bytes.substr(std::min(header.body_start, bytes.size()));
  check_counts(name, header, body);
  TriMesh mesh;
  PlyValueReader reader(name, body, header.format);
  bool have_vertices = false;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") {
      if (have_vertices) throw_error(name, ": PLY has two vertex elements");
      have_vertices = true;
      read_vertices(name, element, reader, mesh);
    } else if (element.name == "face") {
      if (!have_vertices) throw_error(name, ": PLY face element comes before the vertex element");
      read_faces(name, element, reader, mesh);
    } else {
      skip_element(element, reader);
    }
  }
  return mesh;
}

std::string write_ply(const std::string& name, const TriMesh& mesh, bool ascii) {
  for (const auto& [field, values] : mesh.vertex_fields) {
    const bool blank = std::any_of(field.begin(), field.end(), [](char c) {
      return is_space(c) || static_cast<unsigned char>(c) < 0x20;
    });
    if (field.empty() || blank || field == "x" || field == "y" || field == "z") {
      throw_error(name, ": vertex field '", field, "' cannot be a PLY property name");
    }
  }
  std::string out = "ply\n";
  out += ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
  out += "comment written by hipfai, units mm\n";
  out += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  for (const auto& [field, values] : mesh.vertex_fields) out += "property double " + field + "\n";
  out += "element face " + std::to_string(mesh.triangles.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  const std::size_t per_vertex = 3 + mesh.vertex_fields.size();
  out.reserve(out.size() + mesh.vertices.size() * per_vertex * (ascii ? 20 : 8) +
              mesh.triangles.size() * (ascii ? 30 : 13));
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    std::size_t written = 0;
    auto put = [&](double value) {
      if (ascii) {
        append_number(out, value);
        out += ++written < per_vertex ? " " : "\n";
      } else {
        store_little(out, value);
      }
    };
    for (int k = 0; k < 3; ++k) put(mesh.vertices[v][k]);
    for (const auto& [field, values] : mesh.vertex_fields) put(values[v]);
  }
  for (const Triangle& tri : mesh.triangles) {
    if (ascii) {
      out += "3";
      for (const std::int32_t index : tri) {
        out += " ";
        append_number(out, static_cast<std::int64_t>(index));
      }
      out += "\n";
    } else {
      out.push_back(3);
      for (const std::int32_t index : tri) store_little(out, index);
    }
  }
  return out;
}

}  // namespace hipfai::geometry::mesh_io
