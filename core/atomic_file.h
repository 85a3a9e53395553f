// hipfai — whole files written atomically: the bytes go to a temporary file beside the target,
// which is renamed over the target only when completely written. An interrupted or failed write
// therefore never leaves a half file under the target's name, and a reader sees either the old
// file or the new one. Every writer in the tree goes through this header.
//
// The temporary name is "<target>.<pid>-<n>@<host>.partial": unique per process, per write and per
// machine, so two processes (a study's hips run one per process and share caches, or jobs on
// several machines share one on a network filesystem) writing the same target never write into
// one temporary file; the rename then makes one of the whole files win. Temporaries left by killed
// processes are removed by the next writer of the same target on the same machine.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string_view>

namespace hipfai {

// A file being written: write it at partial_path() (with any library: streams, HDF5, ...), then
// commit(). Destroyed without a successful commit() (an exception, an early return), the
// temporary file is removed and the target is left as it was.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& partial_path() const { return partial_; }

  // Renames the temporary file over the target. Throws hipfai::Error
  // "<target>: cannot move the written file into place (<reason>)".
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path partial_;
  bool committed_ = false;
};

// Writes `path` with `write`, which streams the content (binary mode: bytes go out unchanged).
// Throws hipfai::Error "<path>: cannot write (<reason>)" when the file cannot be created, or
// "<path>: write failed" when the stream fails; whatever `write` throws passes through. In every
// failure the temporary file is removed and the target is untouched.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

// The same for content already in memory.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// A folder filled under a temporary name beside `target` (same naming as AtomicFile) and renamed
// into place by commit(), for cache entries made of several files (a generated hip, a finished
// FE run): a folder under the target's name is always whole. Destroyed without commit() or
// keep(), the temporary folder is removed with its content; the folders of processes that died
// before that (killed) are removed by the next AtomicDirectory of the same target.
class AtomicDirectory {
 public:
  // Creates the empty temporary folder. Throws hipfai::Error "<target>: cannot create ...".
  explicit AtomicDirectory(std::filesystem::path target);
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& partial_path() const { return partial_; }

  // Leaves the temporary folder on disk (a failed run whose log an error message points to).
  void keep() { kept_ = true; }

  // Moves the folder into place and returns true. When `target` exists already and
  // `is_complete(target)`, another process made the same entry first (entries are named by a
  // hash of their inputs): theirs stays, this folder is dropped, and false is returned. An
  // incomplete `target` is replaced. Throws hipfai::Error when the move fails.
  bool commit(const std::function<bool(const std::filesystem::path&)>& is_complete);

 private:
  std::filesystem::path target_;
  std::filesystem::path partial_;
  bool committed_ = false;
  bool kept_ = false;
};

}  // namespace hipfai
