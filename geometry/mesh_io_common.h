// hipfai — what the mesh format readers and writers (geometry/mesh_io_*.cpp) share: whole-file
// reading, byte order, locale-independent numbers, a whitespace tokenizer, polygon fans.
// Internal to geometry/: callers use geometry/mesh_io.h.
#pragma once

#include "geometry/tri_mesh.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hipfai::geometry::mesh_io {

// Largest vertex index a TriMesh holds (its indices are int32).
inline constexpr std::int64_t kMaxIndex = std::numeric_limits<std::int32_t>::max();

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

// The whole file in memory (parsers then walk it). Throws hipfai::Error "<path>: no such file",
// "...: is a directory, not a mesh file", "...: cannot open for reading (<reason>)".
std::string read_file_bytes(const std::filesystem::path& path);

// --- byte order: files state theirs; values are converted on the fly so big-endian input
// works on any host.

template <typename T>
T byte_swapped(T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// The T stored at `data` (no alignment needed) in the given byte order.
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

// --- numbers in text: std::from_chars / to_chars are locale-independent and an order of
// magnitude faster than streams.

// The whole token as a number, or nullopt. A leading '+' (which some writers emit and
// from_chars rejects) is accepted.
std::optional<double> parse_double(std::string_view token);
std::optional<std::int64_t> parse_int(std::string_view token);

// Appends the shortest decimal that reads back to the same double.
void append_number(std::string& out, double value);
void append_number(std::string& out, std::int64_t value);

// Whitespace-separated tokens over a text buffer, with 1-based line numbers for messages.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view text, std::size_t start = 0) : text_(text), pos_(start) {}

  // The next token, or an empty view at the end of the text.
  std::string_view next();
  void skip_line();
  // Line of the last token returned (counted only when a message needs it).
  std::size_t line() const;
  // Offset just past the last token returned.
  std::size_t position() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_;
};

// Appends the fan (c0, c_i, c_{i+1}) of a polygon; callers ensure corners.size() >= 3.
void add_fan(TriMesh& mesh, const std::vector<std::int32_t>& corners);

}  // namespace hipfai::geometry::mesh_io
