#include "geometry/mesh_io.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

namespace hipfai::geometry {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kMaxIndex = std::numeric_limits<std::int32_t>::max();

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

// ---------------------------------------------------------------------------------------------
// Byte order. Files state theirs; we convert on the fly so big-endian input works on any host.

template <typename T>
T byte_swapped(T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

template <typename T>
T load(const char* data, bool little_endian_data) {
  T value;
  std::memcpy(&value, data, sizeof(T));
  const bool host_little = std::endian::native == std::endian::little;
  return little_endian_data == host_little ? value : byte_swapped(value);
}

template <typename T>
void store_little(std::string& out, T value) {
  if constexpr (std::endian::native != std::endian::little) value = byte_swapped(value);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// ---------------------------------------------------------------------------------------------
// Numbers in text. std::from_chars is locale-independent and an order of magnitude faster than
// streams; it rejects a leading '+', which some writers emit, so we skip it ourselves.

std::optional<double> parse_double(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parse_int(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
  return value;
}

void append_number(std::string& out, double value) {
  char buffer[32];
  // Shortest representation that reads back to the same double.
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void append_number(std::string& out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

// Whitespace-separated tokens over a text buffer, with 1-based line numbers for messages.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view text, std::size_t start = 0) : text_(text), pos_(start) {}

  // The next token, or an empty view at the end of the text.
  std::string_view next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(begin, pos_ - begin);
  }

  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

  // Line of the last token returned (counted only when a message needs it).
  std::size_t line() const {
    std::size_t end = pos_;
    while (end > 0 && end <= text_.size() && is_space(text_[end - 1])) --end;
    return 1 + static_cast<std::size_t>(std::count(text_.begin(), text_.begin() + end, '\n'));
  }

 private:
  std::string_view text_;
  std::size_t pos_;
};

// ---------------------------------------------------------------------------------------------
// Whole-file reading: one read() into a string, then parsers walk memory.

std::string read_file_bytes(const fs::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw_error(name, ": no such file");
  if (fs::is_directory(status)) throw_error(name, ": is a directory, not a mesh file");
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(name.c_str(), "rb"), &std::fclose);
  if (!file) throw_error(name, ": cannot open for reading (", std::strerror(errno), ")");
  std::string bytes;
  char buffer[1 << 16];
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec) bytes.reserve(static_cast<std::size_t>(size));
  for (;;) {
    const std::size_t got = std::fread(buffer, 1, sizeof(buffer), file.get());
    bytes.append(buffer, got);
    if (got < sizeof(buffer)) break;
  }
  if (std::ferror(file.get())) throw_error(name, ": read error (", std::strerror(errno), ")");
  return bytes;
}

// ---------------------------------------------------------------------------------------------
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

// Appends the fan (c0, c_i, c_{i+1}) of a convex-or-not polygon; callers ensure size >= 3.
void add_fan(TriMesh& mesh, const std::vector<std::int32_t>& corners) {
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
    mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
  }
}

// ---------------------------------------------------------------------------------------------
// STL

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

// ---------------------------------------------------------------------------------------------
// OBJ

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

// ---------------------------------------------------------------------------------------------
// PLY

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

TriMesh read_ply(const std::string& name, std::string_view bytes) {
  if (bytes.substr(0, 3) != "ply" || bytes.size() < 4 || (bytes[3] != '\n' && bytes[3] != '\r')) {
    throw_error(name, ": not a PLY file (does not start with 'ply')");
  }
  const std::size_t header_end = bytes.find("end_header");
  if (header_end == std::string_view::npos) throw_error(name, ": PLY header has no end_header");
  std::size_t body_start = header_end + 10;
  if (body_start < bytes.size() && bytes[body_start] == '\r') ++body_start;
  if (body_start < bytes.size() && bytes[body_start] == '\n') ++body_start;

  // Header, one statement per line.
  std::optional<PlyFormat> format;
  std::vector<PlyElement> elements;
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
    auto fail = [&](auto&&... parts) {
      throw_error(name, ": PLY header line ", line_number, ": ", parts...);
    };
    if (keyword.empty() || keyword == "ply" || keyword == "comment" || keyword == "obj_info") continue;
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
  if (!format) throw_error(name, ": PLY header has no format line");

  // Guard every allocation against counts the body cannot hold: each binary record needs at
  // least its fixed bytes, each text record at least one character and a separator per value.
  const std::string_view body = bytes.substr(std::min(body_start, bytes.size()));
  std::uint64_t needed = 0;
  for (const PlyElement& element : elements) {
    std::uint64_t record = 0;
    for (const PlyProperty& property : element.properties) {
      if (*format == PlyFormat::ascii) {
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

  TriMesh mesh;
  PlyValueReader reader(name, body, *format);
  bool have_vertices = false;
  std::vector<std::int32_t> corners;
  for (const PlyElement& element : elements) {
    if (element.name == "vertex") {
      if (have_vertices) throw_error(name, ": PLY has two vertex elements");
      have_vertices = true;
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
    } else if (element.name == "face") {
      if (!have_vertices) throw_error(name, ": PLY face element comes before the vertex element");
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
    } else {
      // Edges, materials, ...: read past them.
      for (std::uint64_t e = 0; e < element.count; ++e) {
        reader.at(element, e);
        for (const PlyProperty& property : element.properties) {
          const std::int64_t n = property.is_list ? reader.integer(property.count_type) : 1;
          if (n < 0) reader.fail("negative list length ", n);
          for (std::int64_t i = 0; i < n; ++i) reader.value(property.type);
        }
      }
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// VTP (VTK XML PolyData). A small scanner for the subset VTK writes, not a general XML parser.

struct XmlTag {
  std::string name;
  std::map<std::string, std::string> attributes;
  bool closing = false;       // </name>
  bool self_closing = false;  // <name ... />
  std::size_t begin = 0;      // position of '<'
  std::size_t end = 0;        // one past '>'
};

std::string xml_unescape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  static const std::pair<std::string_view, char> entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    if (text[i] == '&') {
      for (const auto& [entity, c] : entities) {
        if (text.substr(i, entity.size()) == entity) {
          out.push_back(c);
          i += entity.size();
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out.push_back(text[i++]);
  }
  return out;
}

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

// The next element tag at or after `from` (comments, <?...?> and <!...> are skipped).
std::optional<XmlTag> next_tag(const std::string& name, std::string_view xml, std::size_t from) {
  for (;;) {
    const std::size_t lt = xml.find('<', from);
    if (lt == std::string_view::npos) return std::nullopt;
    if (xml.substr(lt, 4) == "<!--") {
      const std::size_t close = xml.find("-->", lt);
      if (close == std::string_view::npos) throw_error(name, ": unterminated XML comment");
      from = close + 3;
      continue;
    }
    if (lt + 1 < xml.size() && (xml[lt + 1] == '?' || xml[lt + 1] == '!')) {
      const std::size_t close = xml.find('>', lt);
      if (close == std::string_view::npos) throw_error(name, ": unterminated XML declaration");
      from = close + 1;
      continue;
    }
    XmlTag tag;
    tag.begin = lt;
    std::size_t i = lt + 1;
    if (i < xml.size() && xml[i] == '/') {
      tag.closing = true;
      ++i;
    }
    const std::size_t name_begin = i;
    while (i < xml.size() && !is_space(xml[i]) && xml[i] != '>' && xml[i] != '/') ++i;
    tag.name = std::string(xml.substr(name_begin, i - name_begin));
    for (;;) {
      while (i < xml.size() && is_space(xml[i])) ++i;
      if (i >= xml.size()) throw_error(name, ": unterminated XML tag <", tag.name);
      if (xml[i] == '>') {
        tag.end = i + 1;
        return tag;
      }
      if (xml[i] == '/' && i + 1 < xml.size() && xml[i + 1] == '>') {
        tag.self_closing = true;
        tag.end = i + 2;
        return tag;
      }
      const std::size_t key_begin = i;
      while (i < xml.size() && xml[i] != '=' && !is_space(xml[i]) && xml[i] != '>') ++i;
      const std::string key(xml.substr(key_begin, i - key_begin));
      while (i < xml.size() && is_space(xml[i])) ++i;
      if (i >= xml.size() || xml[i] != '=') throw_error(name, ": malformed XML attribute '", key, "' in <", tag.name, ">");
      ++i;
      while (i < xml.size() && is_space(xml[i])) ++i;
      if (i >= xml.size() || (xml[i] != '"' && xml[i] != '\'')) {
        throw_error(name, ": unquoted XML attribute '", key, "' in <", tag.name, ">");
      }
      const char quote = xml[i++];
      const std::size_t value_end = xml.find(quote, i);
      if (value_end == std::string_view::npos) throw_error(name, ": unterminated XML attribute '", key, "'");
      tag.attributes[key] = xml_unescape(xml.substr(i, value_end - i));
      i = value_end + 1;
    }
  }
}

std::string attribute(const XmlTag& tag, const std::string& key, const std::string& fallback = "") {
  const auto it = tag.attributes.find(key);
  return it == tag.attributes.end() ? fallback : it->second;
}

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

// Reads the DataArray whose opening tag is `open`; returns it and the position after it.
std::pair<DataArray, std::size_t> read_data_array(const VtpContext& context, std::string_view xml,
                                                  const XmlTag& open) {
  const std::string& name = context.name;
  DataArray array;
  array.name = attribute(open, "Name");
  const std::string label = array.name.empty() ? std::string("(unnamed)") : array.name;
  const std::string components = attribute(open, "NumberOfComponents", "1");
  const auto parsed_components = parse_int(components);
  if (!parsed_components || *parsed_components < 1 || *parsed_components > 1024) {
    throw_error(name, ": DataArray '", label, "' has a bad NumberOfComponents '", components, "'");
  }
  array.components = static_cast<int>(*parsed_components);
  const std::string type = attribute(open, "type");
  const auto parsed_type = vtk_type(type);
  if (!parsed_type) throw_error(name, ": DataArray '", label, "' has unsupported type '", type, "'");
  const std::size_t type_size = vtk_type_size(*parsed_type);
  const std::string format = attribute(open, "format", "ascii");
  if (format == "appended") {
    throw_error(name, ": DataArray '", label,
                "' uses appended data, which is not supported (save as inline binary or ascii)");
  }
  if (format != "ascii" && format != "binary") {
    throw_error(name, ": DataArray '", label, "' has unknown format '", format, "'");
  }
  if (open.self_closing) return {array, open.end};
  const std::size_t close = xml.find("</DataArray>", open.end);
  if (close == std::string_view::npos) throw_error(name, ": DataArray '", label, "' is not closed");
  const std::string_view content = xml.substr(open.end, close - open.end);

  if (format == "ascii") {
    Tokenizer tokens(content);
    for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
      const auto value = parse_double(token);
      if (!value) throw_error(name, ": DataArray '", label, "': bad number '", token, "'");
      array.values.push_back(*value);
    }
  } else {
    const std::vector<unsigned char> bytes = decode_base64(name, label, content);
    if (bytes.size() < context.header_bytes) {
      throw_error(name, ": DataArray '", label, "': binary data shorter than its header");
    }
    const char* data = reinterpret_cast<const char*>(bytes.data());
    const std::uint64_t block = context.header_bytes == 8
                                    ? load<std::uint64_t>(data, context.little_endian)
                                    : load<std::uint32_t>(data, context.little_endian);
    const std::uint64_t available = bytes.size() - context.header_bytes;
    if (block > available) {
      throw_error(name, ": DataArray '", label, "': truncated binary data (header says ", block,
                  " bytes, ", available, " present)");
    }
    if (block % type_size != 0) {
      throw_error(name, ": DataArray '", label, "': ", block, " bytes is not a whole number of ",
                  type, " values");
    }
    array.values.resize(block / type_size);
    vtk_load_all(*parsed_type, data + context.header_bytes, array.values.size(),
                 context.little_endian, array.values);
  }
  return {array, close + 12};
}

// All DataArrays of the section opened by `open`, and the position after its closing tag.
std::pair<std::vector<DataArray>, std::size_t> read_section(const VtpContext& context,
                                                            std::string_view xml, const XmlTag& open) {
  std::vector<DataArray> arrays;
  if (open.self_closing) return {std::move(arrays), open.end};
  std::size_t pos = open.end;
  for (;;) {
    const auto tag = next_tag(context.name, xml, pos);
    if (!tag) throw_error(context.name, ": <", open.name, "> is not closed");
    if (tag->closing && tag->name == open.name) return {std::move(arrays), tag->end};
    if (!tag->closing && tag->name == "DataArray") {
      auto [array, after] = read_data_array(context, xml, *tag);
      arrays.push_back(std::move(array));
      pos = after;
    } else {
      pos = tag->end;
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

TriMesh read_vtp(const std::string& name, std::string_view xml) {
  std::optional<XmlTag> file_tag;
  for (std::size_t pos = 0; !file_tag;) {
    auto tag = next_tag(name, xml, pos);
    if (!tag) throw_error(name, ": not a VTK XML file (no <VTKFile> element)");
    if (!tag->closing && tag->name == "VTKFile") file_tag = std::move(tag);
    else pos = tag->end;
  }
  const std::string type = attribute(*file_tag, "type");
  if (type != "PolyData") throw_error(name, ": VTK file type is '", type, "', not PolyData");
  const std::string compressor = attribute(*file_tag, "compressor");
  if (!compressor.empty()) {
    throw_error(name, ": compressed VTP (", compressor,
                ") is not supported; save the file without compression");
  }
  VtpContext context{name, true, 4};
  const std::string byte_order = attribute(*file_tag, "byte_order", "LittleEndian");
  if (byte_order == "BigEndian") {
    context.little_endian = false;
  } else if (byte_order != "LittleEndian") {
    throw_error(name, ": unknown byte_order '", byte_order, "'");
  }
  const std::string header_type = attribute(*file_tag, "header_type", "UInt32");
  if (header_type == "UInt64") {
    context.header_bytes = 8;
  } else if (header_type != "UInt32") {
    throw_error(name, ": unsupported header_type '", header_type, "'");
  }
  if (xml.find("<AppendedData", file_tag->end) != std::string_view::npos) {
    throw_error(name, ": appended data (<AppendedData>) is not supported; save as inline binary or ascii");
  }

  std::optional<XmlTag> piece;
  std::vector<DataArray> points, point_data, polys, strips;
  bool have_points = false;
  for (std::size_t pos = file_tag->end;;) {
    const auto tag = next_tag(name, xml, pos);
    if (!tag || (tag->closing && tag->name == "VTKFile")) break;
    pos = tag->end;
    if (tag->closing) continue;
    if (tag->name == "Piece") {
      if (piece) throw_error(name, ": VTP files with more than one Piece are not supported");
      piece = *tag;
    } else if (tag->name == "Points" || tag->name == "PointData" || tag->name == "Polys" ||
               tag->name == "Strips" || tag->name == "CellData" || tag->name == "Verts" ||
               tag->name == "Lines") {
      if (!piece) throw_error(name, ": <", tag->name, "> outside a <Piece>");
      auto [arrays, after] = read_section(context, xml, *tag);
      pos = after;
      if (tag->name == "Points") {
        points = std::move(arrays);
        have_points = true;
      } else if (tag->name == "PointData") {
        point_data = std::move(arrays);
      } else if (tag->name == "Polys") {
        polys = std::move(arrays);
      } else if (tag->name == "Strips") {
        strips = std::move(arrays);
      }  // Verts, Lines and CellData carry nothing a surface mesh keeps.
    }
  }
  if (!piece) throw_error(name, ": VTP file has no <Piece>");
  const std::string points_text = attribute(*piece, "NumberOfPoints", "0");
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

// ---------------------------------------------------------------------------------------------
// Writers: each builds the file in memory; write_file_atomically (core/) puts it in place.

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

std::string stl_bytes(const std::string& name, const TriMesh& mesh, bool ascii) {
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

std::string obj_bytes(const TriMesh& mesh) {
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

std::string ply_bytes(const std::string& name, const TriMesh& mesh, bool ascii) {
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

void append_vtp_array(std::string& out, const std::string& attributes,
                      const std::vector<double>& values, bool ascii) {
  out += "        <DataArray type=\"Float64\" " + attributes + " format=\"" +
         (ascii ? "ascii" : "binary") + "\">\n          ";
  if (ascii) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      append_number(out, values[i]);
      out += (i + 1) % 9 == 0 ? "\n          " : " ";
    }
  } else {
    std::string raw;
    raw.reserve(8 + 8 * values.size());
    store_little(raw, static_cast<std::uint64_t>(8 * values.size()));
    for (const double value : values) store_little(raw, value);
    out += encode_base64(raw);
  }
  out += "\n        </DataArray>\n";
}

void append_vtp_index_array(std::string& out, const std::string& array_name,
                            const std::vector<std::int64_t>& values, bool ascii) {
  out += "        <DataArray type=\"Int64\" Name=\"" + array_name + "\" format=\"" +
         (ascii ? "ascii" : "binary") + "\">\n          ";
  if (ascii) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      append_number(out, values[i]);
      out += (i + 1) % 12 == 0 ? "\n          " : " ";
    }
  } else {
    std::string raw;
    raw.reserve(8 + 8 * values.size());
    store_little(raw, static_cast<std::uint64_t>(8 * values.size()));
    for (const std::int64_t value : values) store_little(raw, value);
    out += encode_base64(raw);
  }
  out += "\n        </DataArray>\n";
}

std::string vtp_bytes(const TriMesh& mesh, bool ascii) {
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
  append_vtp_index_array(out, "connectivity", connectivity, ascii);
  append_vtp_index_array(out, "offsets", offsets, ascii);
  out += "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return out;
}

}  // namespace

MeshFormat mesh_format_from_path(const fs::path& path) {
  const std::string extension = lower(path.extension().string());
  if (extension == ".stl") return MeshFormat::stl;
  if (extension == ".obj") return MeshFormat::obj;
  if (extension == ".ply") return MeshFormat::ply;
  if (extension == ".vtp") return MeshFormat::vtp;
  throw_error(path.string(), ": unknown mesh format '", extension.empty() ? "(no extension)" : extension,
              "' (expected .stl, .obj, .ply or .vtp)");
}

std::string to_string(MeshFormat format) {
  switch (format) {
    case MeshFormat::stl: return "STL";
    case MeshFormat::obj: return "OBJ";
    case MeshFormat::ply: return "PLY";
    case MeshFormat::vtp: return "VTP";
  }
  return "?";
}

TriMesh read_mesh(const fs::path& path) {
  const std::string name = path.string();
  const MeshFormat format = mesh_format_from_path(path);
  const std::string bytes = read_file_bytes(path);
  TriMesh mesh;
  switch (format) {
    case MeshFormat::stl: mesh = read_stl(name, bytes); break;
    case MeshFormat::obj: mesh = read_obj(name, bytes); break;
    case MeshFormat::ply: mesh = read_ply(name, bytes); break;
    case MeshFormat::vtp: mesh = read_vtp(name, bytes); break;
  }
  validate_mesh(mesh, name);
  return mesh;
}

void write_mesh(const TriMesh& mesh, const fs::path& path, const MeshWriteOptions& options) {
  const std::string name = path.string();
  const MeshFormat format = mesh_format_from_path(path);
  validate_mesh(mesh, name);
  if (mesh.vertices.size() > static_cast<std::size_t>(kMaxIndex)) {
    throw_error(name, ": too many vertices to write");
  }
  std::string bytes;
  switch (format) {
    case MeshFormat::stl: bytes = stl_bytes(name, mesh, options.ascii); break;
    case MeshFormat::obj: bytes = obj_bytes(mesh); break;
    case MeshFormat::ply: bytes = ply_bytes(name, mesh, options.ascii); break;
    case MeshFormat::vtp: bytes = vtp_bytes(mesh, options.ascii); break;
  }
  write_file_atomically(path, bytes);
}

}  // namespace hipfai::geometry
