#include "geometry/mesh_io_vtp.h"

#include "core/error.h"
#include "geometry/mesh_io_common.h"
#include "geometry/xml_tree.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace hipfai::geometry::mesh_io {
namespace {

std::vector<unsigned char> decode_base64(const std::string& name, const std::string& array,
                                         std::string_view text) {
  static const auto table = [] {
    std::array<int, 256> t{};
    t.fill(-1);
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(alphabet[i])] = i;
    return t;
  }();
  std::vector<unsigned char> out;
  out.reserve(text.size() / 4 * 3);
  // Decoded group by group: VTK may encode the header and the data as separate base64 runs,
  // so padding '=' can appear in the middle of the text.
  int group[4];
  int filled = 0;
  int padding = 0;
  for (const char c : text) {
    if (is_space(c)) continue;
    if (c == '=') {
      group[filled++] = 0;
      ++padding;
    } else {
      const int v = table[static_cast<unsigned char>(c)];
      if (v < 0 || padding > 0) throw_error(name, ": invalid base64 in DataArray '", array, "'");
      group[filled++] = v;
    }
    if (filled == 4) {
      if (padding > 2) throw_error(name, ": invalid base64 in DataArray '", array, "'");
      const std::uint32_t bits = (static_cast<std::uint32_t>(group[0]) << 18) |
                                 (static_cast<std::uint32_t>(group[1]) << 12) |
                                 (static_cast<std::uint32_t>(group[2]) << 6) |
                                 static_cast<std::uint32_t>(group[3]);
      out.push_back(static_cast<unsigned char>(bits >> 16));
      if (padding < 2) out.push_back(static_cast<unsigned char>(bits >> 8));
      if (padding < 1) out.push_back(static_cast<unsigned char>(bits));
      filled = 0;
      padding = 0;
    }
  }
  if (filled != 0) throw_error(name, ": truncated base64 in DataArray '", array, "'");
  return out;
}

struct VtpContext {
  std::string name;
  bool little_endian = true;
  std::size_t header_bytes = 4;  // UInt32 or UInt64 block-size header of binary arrays
};

struct DataArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

enum class VtkType { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64 };

std::optional<VtkType> vtk_type(const std::string& type) {
  static const std::pair<std::string_view, VtkType> names[] = {
      {"Int8", VtkType::int8},     {"UInt8", VtkType::uint8},     {"Int16", VtkType::int16},
      {"UInt16", VtkType::uint16}, {"Int32", VtkType::int32},     {"UInt32", VtkType::uint32},
      {"Int64", VtkType::int64},   {"UInt64", VtkType::uint64},   {"Float32", VtkType::float32},
      {"Float64", VtkType::float64}};
  for (const auto& [text, value] : names) {
    if (text == type) return value;
  }
  return std::nullopt;
}

std::size_t vtk_type_size(VtkType type) {
  switch (type) {
    case VtkType::int8:
    case VtkType::uint8: return 1;
    case VtkType::int16:
    case VtkType::uint16: return 2;
    case VtkType::int32:
    case VtkType::uint32:
    case VtkType::float32: return 4;
    case VtkType::int64:
    case VtkType::uint64:
    case VtkType::float64: return 8;
  }
  return 1;
}

// Converts `count` packed values of one type to doubles (64-bit integers beyond 2^53 round,
// which no index or count of a mesh we can hold reaches).
template <typename T>
void load_all(const char* data, std::size_t count, bool little, std::vector<double>& out) {
  for (std::size_t i = 0; i < count; ++i) out[i] = static_cast<double>(load<T>(data + i * sizeof(T), little));
}

void vtk_load_all(VtkType type, const char* data, std::size_t count, bool little,
                  std::vector<double>& out) {
  switch (type) {
    case VtkType::int8: load_all<std::int8_t>(data, count, little, out); break;
    case VtkType::uint8: load_all<std::uint8_t>(data, count, little, out); break;
    case VtkType::int16: load_all<std::int16_t>(data, count, little, out); break;
    case VtkType::uint16: load_all<std::uint16_t>(data, count, little, out); break;
    case VtkType::int32: load_all<std::int32_t>(data, count, little, out); break;
    case VtkType::uint32: load_all<std::uint32_t>(data, count, little, out); break;
    case VtkType::int64: load_all<std::int64_t>(data, count, little, out); break;
    case VtkType::uint64: load_all<std::uint64_t>(data, count, little, out); break;
    case VtkType::float32: load_all<float>(data, count, little, out); break;
    case VtkType::float64: load_all<double>(data, count, little, out); break;
  }
}

// The DataArray `element` (its format and type checked when its start tag was read).
DataArray read_data_array(const VtpContext& context, const XmlElement& element) {
  const std::string& name = context.name;
  DataArray array;
  array.name = element.attribute("Name");
  const std::string label = array.name.empty() ? std::string("(unnamed)") : array.name;
  const std::string components = element.attribute("NumberOfComponents", "1");
  const auto parsed_components = parse_int(components);
  if (!parsed_components || *parsed_components < 1 || *parsed_components > 1024) {
    throw_error(name, ": DataArray '", label, "' has a bad NumberOfComponents '", components, "'");
  }
  array.components = static_cast<int>(*parsed_components);
  const std::string type = element.attribute("type");
  const auto parsed_type = vtk_type(type);
  if (!parsed_type) throw_error(name, ": DataArray '", label, "' has unsupported type '", type, "'");
  const std::size_t type_size = vtk_type_size(*parsed_type);
  const std::string& content = element.text;
  if (element.attribute("format", "ascii") == "ascii") {
    Tokenizer tokens(content);
    for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
      const auto value = parse_double(token);
      if (!value) throw_error(name, ": DataArray '", label, "': bad number '", token, "'");
      array.values.push_back(*value);
    }
    return array;
  }
  const std::vector<unsigned char> bytes = decode_base64(name, label, content);
  if (bytes.empty()) return array;  // <DataArray .../> or an empty one: no values
  if (bytes.size() < context.header_bytes) {
    throw_error(name, ": DataArray '", label, "': binary data shorter than its header");
  }
  const char* data = reinterpret_cast<const char*>(bytes.data());
  const std::uint64_t block = context.header_bytes == 8 ? load<std::uint64_t>(data, context.little_endian)
                                                        : load<std::uint32_t>(data, context.little_endian);
  const std::uint64_t available = bytes.size() - context.header_bytes;
  if (block > available) {
    throw_error(name, ": DataArray '", label, "': truncated binary data (header says ", block, " bytes, ",
                available, " present)");
  }
  if (block % type_size != 0) {
    throw_error(name, ": DataArray '", label, "': ", block, " bytes is not a whole number of ", type, " values");
  }
  array.values.resize(block / type_size);
  vtk_load_all(*parsed_type, data + context.header_bytes, array.values.size(), context.little_endian,
               array.values);
  return array;
}

// The DataArrays directly inside `section` (Points, PointData, Polys, ...).
std::vector<DataArray> read_section(const VtpContext& context, const XmlElement& section) {
  std::vector<DataArray> arrays;
  for (const auto& child : section.children) {
    if (child->name == "DataArray") arrays.push_back(read_data_array(context, *child));
  }
  return arrays;
}

// Rejects, as soon as its start tag is read, what this reader cannot take: compressed files and
// appended data (raw appended bytes are not even XML, so waiting for the end tag would report a
// parse error instead of the reason).
void check_start_tag(const std::string& name, const XmlElement& element) {
  if (element.name == "VTKFile") {
    const std::string type = element.attribute("type");
    if (type != "PolyData") throw_error(name, ": VTK file type is '", type, "', not PolyData");
    const std::string compressor = element.attribute("compressor");
    if (!compressor.empty()) {
      throw_error(name, ": compressed VTP (", compressor, ") is not supported; save the file without compression");
    }
  } else if (element.name == "AppendedData") {
    throw_error(name, ": appended data (<AppendedData>) is not supported; save as inline binary or ascii");
  } else if (element.name == "DataArray") {
    const std::string label = element.attribute("Name", "(unnamed)");
    const std::string format = element.attribute("format", "ascii");
    if (format == "appended") {
      throw_error(name, ": DataArray '", label,
                  "' uses appended data, which is not supported (save as inline binary or ascii)");
    }
    if (format != "ascii" && format != "binary") {
      throw_error(name, ": DataArray '", label, "' has unknown format '", format, "'");
    }
  }
}

// Turns a connectivity/offsets pair into polygons (or strips) and appends triangles.
void add_cells(const std::string& name, const std::string& section,
               const std::vector<DataArray>& arrays, std::int64_t vertex_count, bool strips,
               TriMesh& mesh) {
  const DataArray* connectivity = nullptr;
  const DataArray* offsets = nullptr;
  for (const DataArray& array : arrays) {
    if (array.name == "connectivity") connectivity = &array;
    if (array.name == "offsets") offsets = &array;
  }
  if (!connectivity || !offsets) {
    throw_error(name, ": <", section, "> needs 'connectivity' and 'offsets' DataArrays");
  }
  auto to_index = [&](double value, const char* what) {
    if (!(value >= 0.0) || value != std::floor(value) || value >= static_cast<double>(vertex_count)) {
      throw_error(name, ": <", section, "> ", what, " value ", value, " out of range (",
                  vertex_count, " points)");
    }
    return static_cast<std::int32_t>(value);
  };
  std::vector<std::int32_t> corners;
  std::size_t begin = 0;
  const auto& ids = connectivity->values;
  for (std::size_t cell = 0; cell < offsets->values.size(); ++cell) {
    const double end_value = offsets->values[cell];
    if (!(end_value >= static_cast<double>(begin)) || end_value > static_cast<double>(ids.size()) ||
        end_value != std::floor(end_value)) {
      throw_error(name, ": <", section, "> offset ", end_value, " of cell ", cell,
                  " is out of order or beyond the ", ids.size(), " connectivity entries");
    }
    const auto end = static_cast<std::size_t>(end_value);
    corners.clear();
    for (std::size_t i = begin; i < end; ++i) corners.push_back(to_index(ids[i], "connectivity"));
    begin = end;
    if (corners.size() < 3) {
      throw_error(name, ": <", section, "> cell ", cell, " has ", corners.size(),
                  " points (at least 3 needed)");
    }
    if (!strips) {
      add_fan(mesh, corners);
      continue;
    }
    // A strip alternates winding: keep every triangle oriented like the first.
    for (std::size_t i = 0; i + 2 < corners.size(); ++i) {
      if (i % 2 == 0) {
        mesh.triangles.push_back({corners[i], corners[i + 1], corners[i + 2]});
      } else {
        mesh.triangles.push_back({corners[i + 1], corners[i], corners[i + 2]});
      }
    }
  }
}

// --- writing

// Attribute values we write (field names) may hold any character.
std::string xml_escape(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out.push_back(c);
    }
  }
  return out;
}

std::string encode_base64(const std::string& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t bits = (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16) |
                               (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8) |
                               static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 2]));
    out.push_back(alphabet[(bits >> 18) & 63]);
    out.push_back(alphabet[(bits >> 12) & 63]);
    out.push_back(alphabet[(bits >> 6) & 63]);
    out.push_back(alphabet[bits & 63]);
  }
  if (i < bytes.size()) {
    std::uint32_t bits = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    const bool two = i + 1 < bytes.size();
    if (two) bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    out.push_back(alphabet[(bits >> 18) & 63]);
    out.push_back(alphabet[(bits >> 12) & 63]);
    out.push_back(two ? alphabet[(bits >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

// One DataArray: Float64 for T = double (points, fields), Int64 for T = std::int64_t (cells).
// Ascii lines hold 9 doubles or 12 indices, about 200 characters.
template <typename T>
void append_vtp_array(std::string& out, const std::string& attributes, const std::vector<T>& values, bool ascii) {
  constexpr bool is_double = std::is_same_v<T, double>;
  const std::size_t per_line = is_double ? 9 : 12;
  out += std::string("        <DataArray type=\"") + (is_double ? "Float64" : "Int64") + "\" " + attributes +
         " format=\"" + (ascii ? "ascii" : "binary") + "\">\n          ";
  if (ascii) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      append_number(out, values[i]);
      out += (i + 1) % per_line == 0 ? "\n          " : " ";
    }
  } else {
    std::string raw;
    raw.reserve(8 + 8 * values.size());
    store_little(raw, static_cast<std::uint64_t>(8 * values.size()));
    for (const T value : values) store_little(raw, value);
    out += encode_base64(raw);
  }
  out += "\n        </DataArray>\n";
}

}  // namespace

TriMesh read_vtp(const std::string& name, std::string_view xml) {
  const std::unique_ptr<XmlElement> file =
      parse_xml(name, xml, [&name](const XmlElement& element) { check_start_tag(name, element); });
  if (file->name != "VTKFile") {
    throw_error(name, ": not a VTK XML file (the root element is <", file->name, ">, not <VTKFile>)");
  }
  VtpContext context{name, true, 4};
  const std::string byte_order = file->attribute("byte_order", "LittleEndian");
  if (byte_order == "BigEndian") {
    context.little_endian = false;
  } else if (byte_order != "LittleEndian") {
    throw_error(name, ": unknown byte_order '", byte_order, "'");
  }
  const std::string header_type = file->attribute("header_type", "UInt32");
  if (header_type == "UInt64") {
    context.header_bytes = 8;
  } else if (header_type != "UInt32") {
    throw_error(name, ": unsupported header_type '", header_type, "'");
  }

  const XmlElement* piece = nullptr;
  for (const auto& poly_data : file->children) {
    if (poly_data->name != "PolyData") continue;
    for (const auto& child : poly_data->children) {
      if (child->name != "Piece") continue;
      if (piece) throw_error(name, ": VTP files with more than one Piece are not supported");
      piece = child.get();
    }
  }
  if (!piece) throw_error(name, ": VTP file has no <Piece>");
  std::vector<DataArray> points, point_data, polys, strips;
  bool have_points = false;
  for (const auto& section : piece->children) {
    if (section->name == "Points") {
      points = read_section(context, *section);
      have_points = true;
    } else if (section->name == "PointData") {
      point_data = read_section(context, *section);
    } else if (section->name == "Polys") {
      polys = read_section(context, *section);
    } else if (section->name == "Strips") {
      strips = read_section(context, *section);
    }  // Verts, Lines and CellData carry nothing a surface mesh keeps.
  }
  const std::string points_text = piece->attribute("NumberOfPoints", "0");
  const auto point_count = parse_int(points_text);
  if (!point_count || *point_count < 0 || *point_count > kMaxIndex) {
    throw_error(name, ": bad NumberOfPoints '", points_text, "'");
  }
  if (!have_points || points.empty()) throw_error(name, ": VTP piece has no <Points> DataArray");
  const DataArray& coordinates = points.front();
  if (coordinates.components != 3 ||
      coordinates.values.size() != 3 * static_cast<std::size_t>(*point_count)) {
    throw_error(name, ": <Points> holds ", coordinates.values.size(), " values in ",
                coordinates.components, " components for ", *point_count, " points (3 each)");
  }
  TriMesh mesh;
  mesh.vertices.resize(static_cast<std::size_t>(*point_count));
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    mesh.vertices[v] = Vec3(coordinates.values[3 * v], coordinates.values[3 * v + 1],
                            coordinates.values[3 * v + 2]);
  }
  for (DataArray& array : point_data) {
    if (array.components != 1) continue;  // vectors (normals, displacements) are not scalar fields
    if (array.name.empty()) throw_error(name, ": <PointData> has a DataArray without a Name");
    if (array.values.size() != mesh.vertices.size()) {
      throw_error(name, ": PointData '", array.name, "' has ", array.values.size(), " values for ",
                  mesh.vertices.size(), " points");
    }
    mesh.vertex_fields[array.name] = std::move(array.values);
  }
  if (!polys.empty()) add_cells(name, "Polys", polys, *point_count, false, mesh);
  if (!strips.empty()) add_cells(name, "Strips", strips, *point_count, true, mesh);
  return mesh;
}

std::string write_vtp(const TriMesh& mesh, bool ascii) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<!-- written by hipfai, units mm -->\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n  <PolyData>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.vertices.size()) +
         "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
         std::to_string(mesh.triangles.size()) + "\">\n";
  out += "      <PointData";
  if (!mesh.vertex_fields.empty()) {
    out += " Scalars=\"" + xml_escape(mesh.vertex_fields.begin()->first) + "\"";
  }
  out += ">\n";
  for (const auto& [field, values] : mesh.vertex_fields) {
    append_vtp_array(out, "Name=\"" + xml_escape(field) + "\"", values, ascii);
  }
  out += "      </PointData>\n      <Points>\n";
  std::vector<double> coordinates;
  coordinates.reserve(3 * mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  append_vtp_array(out, "Name=\"Points\" NumberOfComponents=\"3\"", coordinates, ascii);
  out += "      </Points>\n      <Polys>\n";
  std::vector<std::int64_t> connectivity, offsets;
  connectivity.reserve(3 * mesh.triangles.size());
  offsets.reserve(mesh.triangles.size());
  for (const Triangle& tri : mesh.triangles) {
    connectivity.insert(connectivity.end(), {tri[0], tri[1], tri[2]});
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  append_vtp_array(out, "Name=\"connectivity\"", connectivity, ascii);
  append_vtp_array(out, "Name=\"offsets\"", offsets, ascii);
  out += "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return out;
}

}  // namespace hipfai::geometry::mesh_io
