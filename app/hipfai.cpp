// hipfai — command-line entry point: builds the sub-command tree and maps errors to exit codes.
#include "app/command_registry.h"
#include "core/error.h"
#include "core/version.h"

#include <algorithm>
#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{
      "hipfai: fast collision detection, penetration depth, range of motion and FE contact "
      "for the human hip (after Arbabi 2009)"};
  app.require_subcommand(1);
  // Parse errors in one line, like every other hipfai error.
  app.failure_message([](const CLI::App* failed, const CLI::Error& e) {
    return "hipfai: error: " + std::string(e.what()) + " (see '" + failed->get_name() +
           " --help')\n";
  });
  app.set_version_flag("--version", std::string(hipfai::kVersion) + " (" + hipfai::kGitSha + ")");

  auto& registry = hipfai::app::command_registry();
  std::sort(registry.begin(), registry.end(),
            [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& command : registry) command.add(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const hipfai::Error& e) {
    std::cerr << "hipfai: error: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "hipfai: internal error: " << e.what() << '\n';
    return 3;
  }
  return 0;
}
