// hipfai — a cache entry made once, whole, however many jobs ask for it at the same time.
//
// The caches of hipfai (generated hips, FE runs) are folders named by a hash of their inputs, and
// several jobs may share one: two studies of two users, two scheduler jobs, the ranks of one job
// on a cluster's shared filesystem. make_cache_entry() combines two mechanisms:
//  - a per-entry lock (core/file_lock.h, "<entry>.lock", flock), held while the entry is made: a
//    second job asking for the same entry waits for it (or, with LockWait::kTry, does other work
//    first) and then reads the first job's entry instead of paying for the same run again. Locks
//    rather than racing atomic renames because an FE run costs minutes: with renames alone both
//    jobs would pay for it and one copy would be thrown away.
//  - the entry filled under a temporary name and renamed into place (core/atomic_file.h,
//    AtomicDirectory): an entry under its name is always whole, also where the filesystem has no
//    locks (then both jobs may make it; the second rename keeps the first, complete, entry).
// A job killed with SIGKILL while making an entry leaves no entry (only its temporary folder,
// removed by the next maker of that entry) and no lock (the kernel drops it with the process), so
// a re-run makes the entry cleanly and takes everything else from the cache.
#pragma once

#include "core/atomic_file.h"
#include "core/file_lock.h"

#include <filesystem>
#include <functional>

namespace hipfai {

enum class EntrySource {
  kFound,          // complete before the call: nothing made
  kMade,           // made by this call
  kMadeElsewhere,  // made by another job (or thread) while this call waited for the lock
  kBusy,           // LockWait::kTry only: another job is making it now; nothing done
};

// True when the folder is a complete entry (e.g. its last-written file exists).
using EntryIsComplete = std::function<bool(const std::filesystem::path& entry)>;
// Fills the entry's temporary folder (staging.partial_path()); throws on failure (the folder is
// then removed, unless the filler called staging.keep() to leave a log for the message).
using EntryFiller = std::function<void(AtomicDirectory& staging)>;

// The lock file of an entry: "<entry>.lock" beside it.
std::filesystem::path cache_entry_lock_path(const std::filesystem::path& entry);

// Makes sure `entry` exists and is complete, making it with `fill` only when no job has made it
// and none is making it. The entry's parent folder is created. Throws what `fill` throws, and
// hipfai::Error when the entry cannot be locked or moved into place.
EntrySource make_cache_entry(const std::filesystem::path& entry, const EntryIsComplete& is_complete,
                             const EntryFiller& fill, LockWait wait = LockWait::kBlock);

}  // namespace hipfai
