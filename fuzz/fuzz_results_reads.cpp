#include "fuzz_results_reads.h"

#include "core/error.h"
#include "studies/results/results_file.h"

#include <exception>
#include <functional>
#include <utility>

namespace hipfai::fuzz {

void read_results_file(const std::filesystem::path& path) {
  // Every read made in one child process (studies/results/hdf5_child.h), the answers kept for the calls below.
  studies::ResultsReader file(path);
  file.prefetch({"/steps/rotation", "/steps/angle_deg", "/steps/index", "/steps/names", "/total"},
                {{"/", "code_version"}, {"/steps/rotation", "units"}, {"/", "body_weight_n"}});
  std::exception_ptr first_error;
  const auto attempt = [&](const std::function<void()>& read) {
    try {
      read();
    } catch (const Error&) {
      if (!first_error) first_error = std::current_exception();
    }
  };
  for (const char* dataset :
       {"/steps/rotation", "/steps/angle_deg", "/steps/index", "/steps/names", "/total"}) {
    attempt([&] {
      std::size_t rows = 0, cols = 0;
      (void)file.dataset(dataset, &rows, &cols);
    });
  }
  for (const auto& attribute :
       {std::pair{"/", "code_version"}, std::pair{"/steps/rotation", "units"},
        std::pair{"/", "body_weight_n"}}) {
    attempt([&] { (void)file.string_attribute(attribute.first, attribute.second); });
  }
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace hipfai::fuzz
