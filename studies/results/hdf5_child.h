// hipfai — HDF5 decoding in a child process, so that a file that crashes HDF5 cannot crash hipfai.
//
// Debian's HDF5 (1.10.8) crashes on some damaged files: decoding a corrupt attribute message it
// reads past its buffers, uses freed memory or dereferences garbage (docs/fuzzing.md,
// tests/data/hdf5-crashes/), and nothing a reader can check beforehand stops it, because the damage
// is in the metadata HDF5 decodes when an object is opened; whether it crashes depends on the
// order of the calls and on the state of HDF5's caches. So the readers of studies/results/results_file.h
// never decode a file in the reading process: a forked child opens the file, makes the reads,
// and writes plain values to a pipe. A child that dies (a signal, a sanitizer's abort, an error
// status, the time limit) is a one-line refusal of the file, and the reading process goes on.
#pragma once

#include "core/error.h"

#include <filesystem>
#include <functional>
#include <string>

namespace hipfai::studies {

// The refusal: a file whose decoding killed the child (callers may word other errors their own way).
class DamagedHdf5File : public Error {
 public:
  explicit DamagedHdf5File(const std::string& message) : Error(message) {}
};

// Runs `work` in a forked child; `work` writes its answer to the file descriptor it is given, and
// the bytes written are returned. Throws DamagedHdf5File("FILE: damaged HDF5 file: ...") when the
// child does not exit normally with status 0 within the time limit. `file` only names the file in
// the message.
std::string run_hdf5_in_child(const std::filesystem::path& file, const std::function<void(int fd)>& work);

// The time a child may take (default 300 s; the fuzzer sets less than its own per-input limit).
void set_hdf5_child_seconds(unsigned seconds);

namespace detail {
// run_hdf5_in_child with an explicit time limit (tests: children that crash, fail or hang).
std::string run_in_child(const std::filesystem::path& file, const std::function<void(int fd)>& work,
                         unsigned seconds);
}  // namespace detail

}  // namespace hipfai::studies
