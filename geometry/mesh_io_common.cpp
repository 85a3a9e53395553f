#include "geometry/mesh_io_common.h"

#include "core/error.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <memory>
#include <system_error>

namespace hipfai::geometry::mesh_io {

std::string read_file_bytes(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
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

namespace {

template <typename T>
std::optional<T> parse_number(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  T value{};
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
  return value;
}

template <typename T>
void append(std::string& out, T value) {
  char buffer[32];  // the longest double (24 characters) or int64 (20) fits
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

}  // namespace

std::optional<double> parse_double(std::string_view token) { return parse_number<double>(token); }
std::optional<std::int64_t> parse_int(std::string_view token) { return parse_number<std::int64_t>(token); }

void append_number(std::string& out, double value) { append(out, value); }
void append_number(std::string& out, std::int64_t value) { append(out, value); }

std::string_view Tokenizer::next() {
  while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
  const std::size_t begin = pos_;
  while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
  return text_.substr(begin, pos_ - begin);
}

void Tokenizer::skip_line() {
  while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
}

std::size_t Tokenizer::line() const {
  std::size_t end = pos_;
  while (end > 0 && end <= text_.size() && is_space(text_[end - 1])) --end;
  return 1 + static_cast<std::size_t>(std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
}

void add_fan(TriMesh& mesh, const std::vector<std::int32_t>& corners) {
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
    mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
  }
}

}  // namespace hipfai::geometry::mesh_io
