#include "core/atomic_file.h"

#include "core/error.h"

#include <atomic>
#include <cctype>
#include <charconv>
#include <csignal>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>
#include <unistd.h>

namespace hipfai {
namespace {

// This machine's name as it may stand in a file name (characters other than letters, digits, '-'
// and '_' as '_').
const std::string& host_tag() {
  static const std::string tag = [] {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return std::string("unknown");
    std::string text(name);
    for (char& c : text) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
    }
    return text.empty() ? std::string("unknown") : text;
  }();
  return tag;
}

std::filesystem::path partial_path_for(const std::filesystem::path& target) {
  static std::atomic<unsigned long> counter{0};
  return target.string() + "." + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "@" + host_tag() +
         ".partial";
}

// A process that exists and has not terminated. A killed process whose parent died too can stay a
// zombie (state Z in /proc/<pid>/stat) where PID 1 does not reap, e.g. in containers: kill(pid, 0)
// still succeeds for it, but it will never finish its folder.
bool process_is_running(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!stat || !std::getline(stat, line)) return true;  // cannot tell: assume it runs
  const std::size_t close = line.rfind(')');            // the command name may hold spaces and ')'
  if (close == std::string::npos || close + 2 >= line.size()) return true;
  const char state = line[close + 2];
  return state != 'Z' && state != 'X';
}

// Removes the temporary files or folders of `target` left by processes of this machine that no
// longer exist (killed before they could clean up). Those of live processes, including this one,
// are theirs; so are those of other machines sharing the folder ("@<host>" in the name), whose
// processes cannot be looked at from here.
void remove_orphaned_partials(const std::filesystem::path& target) {
  const std::string prefix = target.filename().string() + ".";
  const std::string suffix = ".partial";
  const std::filesystem::path parent = target.has_parent_path() ? target.parent_path() : ".";
  std::vector<std::filesystem::path> orphans;
  std::error_code error;
  for (std::filesystem::directory_iterator it(parent, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 || !name.ends_with(suffix)) continue;
    const std::string_view middle(name.data() + prefix.size(), name.size() - prefix.size() - suffix.size());
    long pid = 0;  // "<pid>-<n>"
    const auto [end_of_pid, parsed] = std::from_chars(middle.data(), middle.data() + middle.size(), pid);
    if (parsed != std::errc() || end_of_pid == middle.data() + middle.size() || *end_of_pid != '-') continue;
    if (pid <= 0 || pid == ::getpid()) continue;
    const std::size_t at = middle.find('@');
    if (at != std::string_view::npos && middle.substr(at + 1) != host_tag()) continue;
    if (process_is_running(static_cast<pid_t>(pid))) continue;
    orphans.push_back(it->path());
  }
  for (const auto& orphan : orphans) std::filesystem::remove_all(orphan, error);
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target)
    : target_(std::move(target)), partial_(partial_path_for(target_)) {
  remove_orphaned_partials(target_);
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  std::error_code ignored;  // nothing may be thrown here; a missing file is fine
  std::filesystem::remove(partial_, ignored);
}

void AtomicFile::commit() {
  std::error_code error;
  std::filesystem::rename(partial_, target_, error);
  if (error) {
    throw_error(target_.string(), ": cannot move the written file into place (", error.message(), ")");
  }
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write) {
  AtomicFile file(path);
  {
    std::ofstream out(file.partial_path(), std::ios::binary | std::ios::trunc);
    if (!out) throw_error(path.string(), ": cannot write (", std::strerror(errno), ")");
    write(out);
    out.close();
    if (!out) throw_error(path.string(), ": write failed");
  }
  file.commit();
}

AtomicDirectory::AtomicDirectory(std::filesystem::path target)
    : target_(std::move(target)), partial_(partial_path_for(target_)) {
  remove_orphaned_partials(target_);
  std::error_code error;
  std::filesystem::create_directories(partial_, error);
  if (error) throw_error(target_.string(), ": cannot create the folder to fill (", error.message(), ")");
}

AtomicDirectory::~AtomicDirectory() {
  if (committed_ || kept_) return;
  std::error_code ignored;  // nothing may be thrown here
  std::filesystem::remove_all(partial_, ignored);
}

bool AtomicDirectory::commit(const std::function<bool(const std::filesystem::path&)>& is_complete) {
  std::error_code error;
  std::filesystem::rename(partial_, target_, error);  // fails on an existing non-empty folder
  if (!error) {
    committed_ = true;
    return true;
  }
  if (std::filesystem::exists(target_) && is_complete(target_)) return false;  // the destructor drops ours
  std::error_code ignored;
  std::filesystem::remove_all(target_, ignored);
  std::filesystem::rename(partial_, target_, error);
  if (error) {
    throw_error(target_.string(), ": cannot move the finished folder into place (", error.message(), ")");
  }
  committed_ = true;
  return true;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
  write_file_atomically(path, [bytes](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace hipfai
