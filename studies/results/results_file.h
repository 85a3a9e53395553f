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
#include <map>
#include <string>
#include <utility>
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

// Reads a results file (or any HDF5 file of numbers and string attributes). HDF5 decodes the file
// only in a child process (studies/results/hdf5_child.h): the reads are made there and their values come
// back through a pipe, so a file that crashes HDF5 is refused with a one-line error
// (DamagedHdf5File) instead of crashing the reader. prefetch() makes many reads in one child;
// a read not prefetched gets a child of its own.
class ResultsReader {
 public:
  explicit ResultsReader(std::filesystem::path file);
  ~ResultsReader();
  ResultsReader(const ResultsReader&) = delete;
  ResultsReader& operator=(const ResultsReader&) = delete;

  // Reads these datasets and string attributes ((object, name) pairs) in one child process and
  // keeps each answer, a value or the error its read gave, for the calls below. Throws
  // DamagedHdf5File when the child dies.
  void prefetch(const std::vector<std::string>& datasets,
                const std::vector<std::pair<std::string, std::string>>& attributes);

  // A dataset of numbers as doubles: values row-major; rows = the first extent, cols = the
  // product of the others (a scalar is 1 x 1). Throws hipfai::Error for a missing file or dataset,
  // a file that is not HDF5, a dataset that is not numbers or claims more values than the file
  // stores.
  std::vector<double> dataset(const std::string& path, std::size_t* rows = nullptr, std::size_t* cols = nullptr);
  // One fixed-length string attribute of `object` ("/" for the file).
  std::string string_attribute(const std::string& object, const std::string& name);

 private:
  struct Entry {
    std::string error;  // non-empty: the read's error message
    std::uint64_t rows = 0, cols = 0;
    std::vector<double> values;
    std::string text;
  };
  std::filesystem::path file_;
  std::map<std::string, Entry> datasets_;
  std::map<std::pair<std::string, std::string>, Entry> attributes_;
};

// One read through a ResultsReader (for tests and reports reading a single value of a file).
std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& path,
                                 std::size_t* rows = nullptr, std::size_t* cols = nullptr);
std::string read_string_attribute(const std::filesystem::path& file, const std::string& object,
                                  const std::string& name);

}  // namespace hipfai::studies
