// hipfai — sub-command registry of the command-line program.
//
// Each app/cmd_<name>.cpp defines one sub-command and registers it with a static
// CommandRegistrar; main() builds the CLI11 tree from the registry. The program stays thin:
// a sub-command parses and validates its options, then calls library code.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hipfai::app {

struct Command {
  std::string name;
  // Adds the sub-command to `parent`; the callback set on it runs the command. A callback
  // reports failures by throwing hipfai::Error; main() turns that into a one-line error.
  std::function<void(CLI::App& parent)> add;
};

inline std::vector<Command>& command_registry() {
  static std::vector<Command> registry;
  return registry;
}

struct CommandRegistrar {
  CommandRegistrar(std::string name, std::function<void(CLI::App&)> add) {
    command_registry().push_back({std::move(name), std::move(add)});
  }
};

}  // namespace hipfai::app
