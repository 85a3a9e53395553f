#include "studies/hdf5_child.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

// A sanitizer's death callback (libFuzzer registers one that saves the input as a crash) belongs
// to the parent: the child clears it, so a sanitizer abort inside HDF5 ends only the child.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace hipfai::studies {

namespace {

std::atomic<unsigned> child_seconds{300};

[[noreturn]] void run_child(const std::function<void(int)>& work, int fd, unsigned seconds) {
  for (const int signal_number : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) {
    ::signal(signal_number, SIG_DFL);
  }
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  // HDF5's complaints and a sanitizer's report inside it become the parent's one-line error.
  const int null_fd = ::open("/dev/null", O_WRONLY);
  if (null_fd >= 0) {
    ::dup2(null_fd, STDERR_FILENO);
    ::dup2(null_fd, STDOUT_FILENO);
  }
  ::alarm(seconds);
  try {
    work(fd);
  } catch (...) {
    ::_exit(2);  // `work` reports its own errors in its answer; anything else is a failure
  }
  ::close(fd);
  ::_exit(0);
}

std::string describe(int status, unsigned seconds) {
  if (WIFSIGNALED(status)) {
    const int number = WTERMSIG(status);
    if (number == SIGALRM) return "HDF5 did not finish decoding it within " + std::to_string(seconds) + " s";
    const char* name = ::sigabbrev_np(number);
    return "the HDF5 library crashed decoding it (SIG" + std::string(name ? name : "?") + ")";
  }
  return "the HDF5 library failed decoding it (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
}

}  // namespace

void set_hdf5_child_seconds(unsigned seconds) { child_seconds = seconds > 0 ? seconds : 1; }

std::string run_hdf5_in_child(const std::filesystem::path& file, const std::function<void(int fd)>& work) {
  return detail::run_in_child(file, work, child_seconds);
}

std::string detail::run_in_child(const std::filesystem::path& file, const std::function<void(int fd)>& work,
                                 unsigned seconds) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw_error(file.string(), ": cannot read the HDF5 file (pipe: ", std::strerror(errno), ")");
  }
  const pid_t child = ::fork();
  if (child < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw_error(file.string(), ": cannot read the HDF5 file (fork: ", std::strerror(error), ")");
  }
  if (child == 0) {
    ::close(fds[0]);
    run_child(work, fds[1], seconds);
  }
  ::close(fds[1]);
  std::string answer;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(fds[0], buffer, sizeof buffer);
    if (got > 0) {
      answer.append(buffer, static_cast<std::size_t>(got));
    } else if (got == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw_error(file.string(), ": cannot read the HDF5 file (waitpid: ", std::strerror(errno), ")");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return answer;
  throw DamagedHdf5File(file.string() + ": damaged HDF5 file: " + describe(status, seconds) + "; not read");
}

}  // namespace hipfai::studies
