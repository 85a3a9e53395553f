// hipfai — error type shared by every module.
//
// Every failure the user can cause (bad file, bad option, bad scene) is reported by throwing
// hipfai::Error with a one-line message that names the thing at fault ("femur.stl: truncated
// binary STL: 1204 of 3 000 triangles"). The command-line program catches it, prints
// "hipfai: error: <message>" and exits with a non-zero status.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace hipfai {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Builds the message from streamable parts: throw_error("file.stl", ": ", n, " triangles").
template <typename... Parts>
[[noreturn]] void throw_error(Parts&&... parts) {
  std::ostringstream out;
  (out << ... << std::forward<Parts>(parts));
  throw Error(out.str());
}

}  // namespace hipfai
