// hipfai — numbers as text for reports and tables.
#pragma once

#include <cstdio>
#include <string>

namespace hipfai {

// `value` with `digits` decimals ("%.*f").
inline std::string fixed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

}  // namespace hipfai
