#include "core/child_process.h"

#include "core/error.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/personality.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

// A sanitizer's death callback (libFuzzer registers one that saves the input as a crash) belongs
// to the parent: the child clears it, so a sanitizer abort inside the library ends only the child.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace hipfai {

namespace {

[[noreturn]] void run_child(const std::function<void(int)>& work, int fd, const ChildRequest& request) {
  for (const int signal_number : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) {
    ::signal(signal_number, SIG_DFL);
  }
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  if (request.silence_output) {
    // The library's complaints and a sanitizer's report inside it become the parent's one line.
    const int null_fd = ::open("/dev/null", O_WRONLY);
    if (null_fd >= 0) {
      ::dup2(null_fd, STDERR_FILENO);
      ::dup2(null_fd, STDOUT_FILENO);
    }
  }
  if (request.seconds > 0) ::alarm(request.seconds);
  try {
    work(fd);
  } catch (...) {
    ::_exit(2);  // `work` reports its own errors in its answer; anything else is a failure
  }
  ::close(fd);
  ::_exit(0);  // no atexit handlers, no static destructors: they belong to the parent
}

}  // namespace

std::string ChildOutcome::failure(unsigned seconds) const {
  if (ok) return "";
  if (timed_out) return "did not finish within " + std::to_string(seconds) + " s";
  if (signal_number != 0) return "crashed (" + signal_name() + ")";
  return "exit status " + std::to_string(exit_status);
}

std::string ChildOutcome::signal_name() const {
  if (signal_number == 0) return "";
  const char* name = ::sigabbrev_np(signal_number);
  return "SIG" + std::string(name ? name : "?");
}

bool write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t put = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (put > 0) {
      done += static_cast<std::size_t>(put);
    } else if (put < 0 && errno != EINTR) {
      return false;
    }
  }
  return true;
}

ChildOutcome run_in_child(const std::function<void(int fd)>& work, const ChildRequest& request,
                          const std::string& what) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw_error(what, " (pipe: ", std::strerror(errno), ")");
  const pid_t child = ::fork();
  if (child < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw_error(what, " (fork: ", std::strerror(error), ")");
  }
  if (child == 0) {
    ::close(fds[0]);
    run_child(work, fds[1], request);
  }
  ::close(fds[1]);
  ChildOutcome outcome;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(fds[0], buffer, sizeof buffer);
    if (got > 0) {
      outcome.answer.append(buffer, static_cast<std::size_t>(got));
    } else if (got == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw_error(what, " (waitpid: ", std::strerror(errno), ")");
  }
  if (WIFEXITED(status)) {
    outcome.exit_status = WEXITSTATUS(status);
    outcome.ok = outcome.exit_status == 0;
  } else if (WIFSIGNALED(status)) {
    outcome.signal_number = WTERMSIG(status);
    outcome.timed_out = outcome.signal_number == SIGALRM && request.seconds > 0;
  }
  return outcome;
}


void exec_fresh_image(const std::string& variable, const std::string& value, int fd) {
  const int flags = ::fcntl(fd, F_GETFD);
  if (flags < 0 || ::fcntl(fd, F_SETFD, flags & ~FD_CLOEXEC) != 0) return;
  std::vector<std::string> env_text;
  const std::string prefix = variable + "=";
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    if (std::strncmp(*e, prefix.c_str(), prefix.size()) != 0) env_text.emplace_back(*e);
  }
  env_text.push_back(prefix + value);
  std::vector<char*> envp;
  for (std::string& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::string name = "hipfai-child";
  char* argv[] = {name.data(), nullptr};
  // The new image's addresses the same on every run (where the system allows it: a container's
  // seccomp policy may refuse, and the image then runs at random addresses).
  const int persona = ::personality(0xffffffff);
  if (persona != -1) ::personality(static_cast<unsigned long>(persona) | ADDR_NO_RANDOMIZE);
  ::execve("/proc/self/exe", argv, envp.data());
  if (persona != -1) ::personality(static_cast<unsigned long>(persona));
  ::fcntl(fd, F_SETFD, flags);
}

int run_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                const std::filesystem::path& log, const std::vector<std::string>& environment) {
  std::vector<std::string> argv_text{program.string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_text = environment;
  std::vector<char*> envp;
  for (std::string& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);
  const int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log_fd < 0) return -1;
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl took effect
    ::dup2(log_fd, STDOUT_FILENO);
    ::dup2(log_fd, STDERR_FILENO);
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  ::close(log_fd);
  if (pid < 0) return -1;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace hipfai
