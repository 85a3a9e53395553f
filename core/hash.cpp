#include "core/hash.h"

#include "core/error.h"

#include <cstring>
#include <fstream>
#include <vector>

namespace hipfai {

Hasher& Hasher::add(std::string_view bytes) {
  for (const char c : bytes) {
    state_ ^= static_cast<unsigned char>(c);
    state_ *= 0x100000001b3ULL;
  }
  // A separator so that ("ab", "c") and ("a", "bc") differ.
  state_ ^= 0xff;
  state_ *= 0x100000001b3ULL;
  return *this;
}

Hasher& Hasher::add(double value) {
  char bytes[sizeof value];
  std::memcpy(bytes, &value, sizeof value);
  return add(std::string_view(bytes, sizeof bytes));
}

Hasher& Hasher::add(std::int64_t value) {
  char bytes[sizeof value];
  std::memcpy(bytes, &value, sizeof value);
  return add(std::string_view(bytes, sizeof bytes));
}

std::string Hasher::hex() const {
  static const char* digits = "0123456789abcdef";
  std::string text(16, '0');
  for (int i = 0; i < 16; ++i) text[15 - i] = digits[(state_ >> (4 * i)) & 0xf];
  return text;
}

std::string hash_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_error(path.string(), ": cannot open file to hash");
  Hasher hasher;
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    hasher.add(std::string_view(buffer.data(), static_cast<std::size_t>(in.gcount())));
  }
  return hasher.hex();
}

}  // namespace hipfai
