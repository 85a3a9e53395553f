// hipfai — content hashes for cache keys and provenance (FNV-1a, 64 bit).
//
// Not cryptographic: the hashes name cache entries and record which meshes a result came from.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace hipfai {

class Hasher {
 public:
  Hasher& add(std::string_view bytes);
  Hasher& add(double value);          // by bit pattern: 0.1 and 0.1000000001 differ
  Hasher& add(std::int64_t value);
  std::uint64_t value() const { return state_; }
  std::string hex() const;            // 16 lower-case hex digits

 private:
  std::uint64_t state_ = 0xcbf29ce484222325ULL;
};

// Hash of a file's bytes; throws hipfai::Error if it cannot be read.
std::string hash_file(const std::filesystem::path& path);

}  // namespace hipfai
