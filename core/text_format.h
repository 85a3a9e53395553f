// hipfai — numbers as text for reports, tables and result files.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

namespace hipfai {

// `value` with `digits` decimals ("%.*f").
inline std::string fixed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

// As fixed(), but a value that is not finite (a missing cell) is written as `missing`.
inline std::string fixed_or(double value, int digits, const char* missing) {
  return std::isfinite(value) ? fixed(value, digits) : std::string(missing);
}

// 17 significant digits ("%.17g"): read back, the same double.
inline std::string digits17(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

// The shortest text that reads back as the same double (std::to_chars).
inline std::string shortest(double value) {
  char buffer[64];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), value).ptr;
  return std::string(buffer, end);
}

}  // namespace hipfai
