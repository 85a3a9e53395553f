// hipfai report correlation DIR: re-makes the validation's correlation report (correlation.csv,
// report.md, figures) from the folder's stored per-step results, without computing anything else.
#include "app/command_registry.h"
#include "studies/validation_report.h"

#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

namespace hipfai::app {
namespace {

const CommandRegistrar report_registrar("report", [](CLI::App& parent) {
  auto* report = parent.add_subcommand("report", "Re-make a study's report from its stored results");
  report->require_subcommand(1);
  auto* correlation = report->add_subcommand(
      "correlation", "Correlation report of a validation folder (steps.csv from `hipfai study validate`): "
                     "correlation.csv, report.md with Tables 8-9 and figures");
  auto dir = std::make_shared<std::string>();
  correlation->add_option("DIR", *dir, "Validation output folder")->required()->check(CLI::ExistingDirectory);
  correlation->callback([=] {
    const auto result = studies::write_correlation_report(*dir);
    std::cout << std::fixed << std::setprecision(2) << "report correlation: mean r (primary measure) "
              << result.mean_r_all << " all, " << result.mean_r_curvilinear << " curvilinear, "
              << result.mean_r_radial << " radial over " << result.ok_cells << " cells; " << result.report.string()
              << ", " << result.correlation_csv.string() << '\n';
  });
});

}  // namespace
}  // namespace hipfai::app
