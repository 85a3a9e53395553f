#include "core/file_lock.h"

#include "core/error.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hipfai {
namespace {

bool locks_unsupported(int error) { return error == ENOLCK || error == EOPNOTSUPP || error == ENOSYS || error == EINVAL; }

// flock, retried when a signal interrupts the wait. Returns 0 or the errno.
int lock(int fd, LockWait wait) {
  const int operation = LOCK_EX | (wait == LockWait::kTry ? LOCK_NB : 0);
  for (;;) {
    if (::flock(fd, operation) == 0) return 0;
    if (errno != EINTR) return errno;
  }
}

// The file locked through `fd` is still the one named `path` (not removed by the holder before).
bool still_named(int fd, const std::filesystem::path& path) {
  struct stat opened {}, named {};
  if (::fstat(fd, &opened) != 0 || ::stat(path.c_str(), &named) != 0) return false;
  return opened.st_dev == named.st_dev && opened.st_ino == named.st_ino;
}

}  // namespace

FileLock::FileLock(std::filesystem::path path, LockWait wait) : path_(std::move(path)) {
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw_error(path_.string(), ": cannot create the lock file (", std::strerror(errno), ")");
    const int error = lock(fd_, wait);
    if (error == 0 && still_named(fd_, path_)) {
      state_ = LockState::kHeld;
      return;
    }
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      state_ = LockState::kBusy;
      return;
    }
    if (error != 0) {
      if (!locks_unsupported(error)) throw_error(path_.string(), ": cannot lock (", std::strerror(error), ")");
      state_ = LockState::kUnlocked;
      return;
    }
    // Locked a file its holder had removed on release: lock the one under the name now.
  }
}

FileLock::~FileLock() {
  if (fd_ < 0) return;
  // Removed while still held: a waiter then finds its file gone and opens the name again.
  if (state_ == LockState::kHeld) ::unlink(path_.c_str());
  ::flock(fd_, LOCK_UN);  // explicitly: a forked child sharing the descriptor must not keep it
  ::close(fd_);
}

}  // namespace hipfai
