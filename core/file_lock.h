// hipfai — an exclusive lock on a file (flock), the way concurrent jobs sharing a cache agree on
// who makes an entry (core/cache_entry.h).
//
// Why flock and not a lock file created with O_EXCL: the kernel drops an flock lock when the
// process holding it dies, SIGKILL included, so a job killed by a scheduler never leaves a stale
// lock behind that would block the next one. The lock belongs to the open file description, so
// two threads of one process that each construct a FileLock exclude each other too. The file is
// opened with O_CLOEXEC: a program a locker starts (an FE worker) does not inherit it.
//
// The lock file is removed when the holder releases it, so a cache does not fill with them. That
// is safe because a locker checks, once it holds the lock, that the file it locked is still the one
// under the name (same inode); a waiter that locked a file removed meanwhile opens the name again.
// A killed holder leaves its (empty, unlocked) file, which the next locker takes and removes.
//
// Shared filesystems: on NFS, Linux maps flock onto POSIX byte-range locks, which the server (NFSv4,
// or NLM for v3) arbitrates between machines; Lustre does so when mounted with -o flock. Where the
// filesystem refuses locks (ENOLCK, EOPNOTSUPP), the state is kUnlocked: the caller goes on without
// the lock, and the atomic rename of core/atomic_file.h still keeps every entry whole.
#pragma once

#include <filesystem>

namespace hipfai {

enum class LockWait {
  kBlock,  // wait until the lock is free
  kTry,    // return at once; state() is kBusy when another holder has it
};

enum class LockState {
  kHeld,      // this FileLock holds the lock
  kBusy,      // kTry only: another process or thread holds it
  kUnlocked,  // the filesystem has no locks: nobody is excluded
};

class FileLock {
 public:
  // Opens (creating it when missing) `path` and takes its exclusive lock. Throws hipfai::Error
  // "<path>: cannot create the lock file (<reason>)" when the file cannot be opened.
  FileLock(std::filesystem::path path, LockWait wait);
  ~FileLock();  // releases the lock and removes the file (when held)
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

  LockState state() const { return state_; }
  // True when the caller may go on: held, or no locks on this filesystem.
  bool may_proceed() const { return state_ != LockState::kBusy; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  LockState state_ = LockState::kUnlocked;
};

}  // namespace hipfai
