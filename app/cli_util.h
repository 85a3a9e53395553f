// hipfai — small helpers shared by the sub-commands: 3-vectors and enums on the command line,
// atomic CSV output.
#pragma once

#include "core/atomic_file.h"
#include "core/error.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace hipfai::app {

// Adds an option taking "x,y,z" (three finite numbers).
inline CLI::Option* add_vec3_option(CLI::App* command, const std::string& name,
                                    std::vector<double>& values, const std::string& help) {
  return command->add_option(name, values, help + " (x,y,z)")
      ->delimiter(',')
      ->expected(3)
      ->type_name("X,Y,Z");
}

inline Eigen::Vector3d to_vec3(const std::vector<double>& values, const std::string& name) {
  if (values.size() != 3) throw_error(name, ": expected three numbers x,y,z");
  const Eigen::Vector3d v(values[0], values[1], values[2]);
  if (!v.allFinite()) throw_error(name, ": coordinates must be finite");
  return v;
}

// Writes an output file the user named, creating its folder first (a CLI convenience), through
// core/atomic_file.h so a failure leaves no half-written file.
inline void write_text_atomically(const std::filesystem::path& path,
                                  const std::function<void(std::ostream&)>& write) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  write_file_atomically(path, write);
}

// An option naming one value of an enum by the names its table gives (core/fe_choices.h style:
// to_string(value) for every value of `values`); `target` keeps its value when the option is absent
// and is shown as the default.
template <class Enum, std::size_t N>
CLI::Option* add_enum_option(CLI::App* command, const std::string& name, Enum& target,
                             const std::array<Enum, N>& values, const std::string& help) {
  std::vector<std::string> names;
  for (const Enum value : values) names.emplace_back(to_string(value));
  return command
      ->add_option_function<std::string>(
          name,
          [&target, values](const std::string& text) {
            for (const Enum value : values) {
              if (text == to_string(value)) target = value;
            }
          },
          help)
      ->check(CLI::IsMember(names))
      ->default_str(to_string(target));
}

}  // namespace hipfai::app
