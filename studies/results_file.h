// hipfai — the HDF5 results file every study writes.
//
// A thin RAII wrapper over the HDF5 C API: datasets of doubles or integers with a `units`
// attribute, string attributes for provenance (scene, mesh hashes, code version). The file is
// written under a temporary name and renamed into place by commit(), so an interrupted run never
// leaves a half-written results file behind.
#pragma once

#include "core/atomic_file.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

class ResultsFile {
 public:
  // Creates a temporary file beside `path` (core/atomic_file.h); commit() renames it to `path`.
  // Without commit() the temporary file is removed by the destructor.
  explicit ResultsFile(std::filesystem::path path);
  ~ResultsFile();
  ResultsFile(const ResultsFile&) = delete;
  ResultsFile& operator=(const ResultsFile&) = delete;

  // Creates group `path` (and its parents) if missing, e.g. "/models/ce20_alpha40".
  void create_group(const std::string& path);

  // Writes a dataset of rows x cols doubles (cols = 1 for a vector) with a `units` attribute.
  void write(const std::string& path, const std::vector<double>& values, std::size_t cols,
             const std::string& units);
  void write_integers(const std::string& path, const std::vector<std::int64_t>& values, std::size_t cols,
             const std::string& units);
  void write_strings(const std::string& path, const std::vector<std::string>& values);

  // String / numeric attribute on an existing object ("/" for the file).
  void set_attribute(const std::string& object, const std::string& name, const std::string& value);
  void set_attribute(const std::string& object, const std::string& name, double value);

  void commit();

 private:
  void ensure_parent_groups(const std::string& path);

  AtomicFile atomic_;
  std::int64_t file_ = -1;
  bool committed_ = false;
};

// Reads a results file (or any HDF5 file of numbers and string attributes): the file is first
// walked in a child process (studies/hdf5_probe.h), so a file that crashes HDF5 is refused with
// a one-line error instead of crashing the reader; then it is opened once for all its reads.
class ResultsReader {
 public:
  // Throws hipfai::Error when the file is damaged (the probe), missing or not HDF5.
  explicit ResultsReader(std::filesystem::path file);
  ~ResultsReader();
  ResultsReader(const ResultsReader&) = delete;
  ResultsReader& operator=(const ResultsReader&) = delete;

  // A dataset of numbers as doubles: values row-major; rows = the first extent, cols = the
  // product of the others (a scalar is 1 x 1). Refuses a dataset that is not numbers or claims
  // more values than the file stores.
  std::vector<double> dataset(const std::string& path, std::size_t* rows = nullptr,
                              std::size_t* cols = nullptr) const;
  // One fixed-length string attribute of `object` ("/" for the file).
  std::string string_attribute(const std::string& object, const std::string& name) const;

 private:
  std::filesystem::path file_;
  std::int64_t handle_ = -1;
};

// One read through a ResultsReader (for tests and reports reading a single value of a file).
std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& path,
                                 std::size_t* rows = nullptr, std::size_t* cols = nullptr);
std::string read_string_attribute(const std::filesystem::path& file, const std::string& object,
                                  const std::string& name);

}  // namespace hipfai::studies
