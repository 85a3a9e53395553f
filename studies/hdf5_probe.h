// hipfai — read an HDF5 file once in a child process before this process trusts HDF5 with it.
//
// Debian's HDF5 (1.10.8) crashes on some damaged files: decoding a corrupt attribute message it
// reads past its buffer or dereferences garbage (docs/fuzzing.md, fuzz/hdf5-known/), and nothing
// a reader can check beforehand stops it, because the damage is inside the metadata HDF5 decodes
// when an object is opened. So the readers of studies/results_file.h first let a forked child
// walk the file: every object, every attribute (opened, its type and extent read), every
// dataset's type, extent and storage. If the child dies, the file is refused with a one-line
// error and this process never decodes it; if the child finishes, the file's metadata decode
// without crashing and the reader goes on (its own checks still apply).
#pragma once

#include "core/error.h"

#include <filesystem>
#include <string>

namespace hipfai::studies {

// The probe's refusal: a file whose metadata crash HDF5 (callers may word other errors their own way).
class DamagedHdf5File : public Error {
 public:
  explicit DamagedHdf5File(const std::string& message) : Error(message) {}
};

// Throws DamagedHdf5File("FILE: damaged HDF5 file: ...") when walking the file's metadata crashes
// HDF5 (a signal, or a sanitizer's abort) in a child process. Files HDF5 merely refuses (not
// HDF5, missing) pass: the reader reports those itself. One fork per call: a reader probes a
// file once and then keeps it open (studies/results_file.h's ResultsReader).
void probe_hdf5_file(const std::filesystem::path& file);

namespace detail {
// The probe's mechanism with another walk and time limit (tests: a walk that crashes or hangs).
using Hdf5Walk = void (*)(const std::filesystem::path& file);
void probe_in_child(const std::filesystem::path& file, Hdf5Walk walk, unsigned seconds);
}  // namespace detail

}  // namespace hipfai::studies
