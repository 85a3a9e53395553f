#include "core/cache_entry.h"

#include "core/error.h"

#include <system_error>

namespace hipfai {

std::filesystem::path cache_entry_lock_path(const std::filesystem::path& entry) {
  return entry.string() + ".lock";
}

EntrySource make_cache_entry(const std::filesystem::path& entry, const EntryIsComplete& is_complete,
                             const EntryFiller& fill, LockWait wait) {
  if (is_complete(entry)) return EntrySource::kFound;
  if (entry.has_parent_path()) {
    std::error_code error;
    std::filesystem::create_directories(entry.parent_path(), error);
    if (error) throw_error(entry.parent_path().string(), ": cannot create the cache folder (", error.message(), ")");
  }
  const FileLock lock(cache_entry_lock_path(entry), wait);
  if (!lock.may_proceed()) return EntrySource::kBusy;
  // Looked at again under the lock: the job that held it before may have finished the entry.
  if (is_complete(entry)) return EntrySource::kMadeElsewhere;
  AtomicDirectory staging(entry);
  fill(staging);
  // false: no lock on this filesystem and another job's rename came first; the entry is theirs.
  return staging.commit(is_complete) ? EntrySource::kMade : EntrySource::kMadeElsewhere;
}

}  // namespace hipfai
