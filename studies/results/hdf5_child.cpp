#include "studies/results/hdf5_child.h"

#include "core/child_process.h"

#include <atomic>
#include <string>

namespace hipfai::studies {

namespace {

std::atomic<unsigned> child_seconds{300};

std::string describe(const ChildOutcome& outcome, unsigned seconds) {
  if (outcome.timed_out) return "HDF5 did not finish decoding it within " + std::to_string(seconds) + " s";
  if (outcome.signal_number != 0) return "the HDF5 library crashed decoding it (" + outcome.signal_name() + ")";
  return "the HDF5 library failed decoding it (" + outcome.failure(seconds) + ")";
}

}  // namespace

void set_hdf5_child_seconds(unsigned seconds) { child_seconds = seconds > 0 ? seconds : 1; }

std::string run_hdf5_in_child(const std::filesystem::path& file, const std::function<void(int fd)>& work) {
  return detail::run_in_child(file, work, child_seconds);
}

std::string detail::run_in_child(const std::filesystem::path& file, const std::function<void(int fd)>& work,
                                 unsigned seconds) {
  ChildRequest request;
  request.seconds = seconds;
  ChildOutcome outcome = hipfai::run_in_child(work, request, file.string() + ": cannot read the HDF5 file");
  if (outcome.ok) return std::move(outcome.answer);
  throw DamagedHdf5File(file.string() + ": damaged HDF5 file: " + describe(outcome, seconds) + "; not read");
}

}  // namespace hipfai::studies
