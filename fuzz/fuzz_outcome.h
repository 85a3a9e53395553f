// The one rule of every harness: a reader given any input answers with a value or a
// hipfai::Error. parse_or_error runs the read and swallows only hipfai::Error; anything else
// (another exception, a crash, a sanitizer report) escapes to libFuzzer, which reports it as a
// finding.
#pragma once

#include "core/error.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace hipfai::fuzz {

inline std::string_view bytes_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

template <typename Read>
int parse_or_error(Read&& read) {
  try {
    read();
  } catch (const Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}

}  // namespace hipfai::fuzz
