// hipfai — work done in a forked child process, so that a library that crashes cannot crash hipfai,
// and other programs run as worker processes (run_program).
//
// Some libraries hipfai calls can take the process down on inputs nothing can check beforehand:
// Debian's HDF5 on damaged metadata (studies/results/hdf5_child.h) and gmsh's surface mesher on some
// OpenCASCADE seams (geometry/hip_generator.h). Such calls run in a child made by fork(): the child
// does the work and writes its answer to a pipe; the parent reads it. A child that dies (a signal,
// a sanitizer's abort, an error status, the time limit) is reported as a ChildOutcome, and the
// parent decides how to word it. The child's copy of the parent's memory is a snapshot: locks held
// by other threads stay held in it, so the caller makes sure no other thread is inside the library
// at fork time (for gmsh: the parent holds lock_gmsh() around the call).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace hipfai {

struct ChildRequest {
  unsigned seconds = 0;          // time limit (SIGALRM in the child); 0: none
  bool silence_output = true;    // the child's stdout and stderr go to /dev/null
};

struct ChildOutcome {
  bool ok = false;               // exited normally with status 0
  std::string answer;            // the bytes `work` wrote (when it died: those before it died)
  int signal_number = 0;         // the signal that ended it, or 0
  int exit_status = 0;           // its exit status when it exited (2: `work` threw)
  bool timed_out = false;        // ended by the time limit

  // "crashed (SIGABRT)", "exit status 3" or "did not finish within N s"; "" when ok.
  std::string failure(unsigned seconds) const;
  // "SIGABRT" for the signal that ended it; "" when none did.
  std::string signal_name() const;
};

// Runs `work` in a forked child; `work` writes its answer to the file descriptor it is given (with
// write_all). An exception out of `work` ends the child with status 2. The parent reads while the
// child writes, so answers of any size pass. Throws hipfai::Error only when no child could be
// started (pipe, fork), naming `what`.
ChildOutcome run_in_child(const std::function<void(int fd)>& work, const ChildRequest& request,
                          const std::string& what);

// In a child made by run_in_child: replaces the child's image with a fresh one of this same program
// (/proc/self/exe), its environment this process' plus `variable`=`value`, `fd` kept open across
// the exec (the time limit, the silenced output and the parent's pipe carry over), address space
// randomisation off (ADDR_NO_RANDOMIZE, where allowed). The new image starts from the program's
// initial heap at the same addresses on every run, for libraries whose results depend on the
// addresses they are given; the program must act on `variable` before main (a static initializer
// of the library that set it). Returns only when the exec failed (the caller then does the work
// itself).
void exec_fresh_image(const std::string& variable, const std::string& value, int fd);

// Writes all of `bytes` to `fd` (retrying short writes and EINTR); false on a write error.
bool write_all(int fd, const std::string& bytes);

// Runs `program args...` in a child process (fork and execve) with its stdout and stderr to `log`
// and `environment` as its environment ("NAME=value" each). The child is killed when this process
// dies (PR_SET_PDEATHSIG), so a killed caller leaves no worker behind it. Returns the child's exit
// status; -1 when it could not be started, the log not opened, or a signal ended it.
int run_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                const std::filesystem::path& log, const std::vector<std::string>& environment);

}  // namespace hipfai
