#include "studies/hdf5_probe.h"

#include "core/error.h"

#include <fcntl.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

// A sanitizer's death callback (libFuzzer registers one that saves the input as a crash) belongs
// to the parent: the child clears it, so a sanitizer abort inside HDF5 ends only the child.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace hipfai::studies {

namespace {

// The child's limits: a dataset's values are read when they fit this many bytes (the reader's
// own size checks guard larger ones), and the whole walk must finish within this many seconds.
constexpr std::size_t kMaxValueBytes = std::size_t{16} << 20;
constexpr unsigned kChildSeconds = 300;

void read_values(hid_t object, bool attribute) {
  const hid_t type = attribute ? H5Aget_type(object) : H5Dget_type(object);
  const hid_t space = attribute ? H5Aget_space(object) : H5Dget_space(object);
  const hssize_t points = space < 0 ? -1 : H5Sget_simple_extent_npoints(space);
  const H5T_class_t type_class = type < 0 ? H5T_NO_CLASS : H5Tget_class(type);
  const std::size_t size = type < 0 ? 0 : H5Tget_size(type);
  bool plain = type_class == H5T_INTEGER || type_class == H5T_FLOAT ||
                     (type_class == H5T_STRING && H5Tis_variable_str(type) == 0);
  if (!attribute && plain && points > 0) {
    // The storage a dataset claims must lie within the file before its values are asked for.
    const hsize_t stored = H5Dget_storage_size(object);
    plain = stored > 0;
  }
  if (plain && points > 0 && size > 0 && static_cast<std::size_t>(points) <= kMaxValueBytes / size) {
    const hid_t memory = H5Tget_native_type(type, H5T_DIR_DEFAULT);
    if (memory >= 0) {
      std::vector<unsigned char> buffer(static_cast<std::size_t>(points) * std::max(size, H5Tget_size(memory)));
      if (attribute) {
        (void)H5Aread(object, memory, buffer.data());
      } else {
        (void)H5Dread(object, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data());
      }
      H5Tclose(memory);
    }
  }
  if (!attribute) {
    const hid_t create = H5Dget_create_plist(object);
    if (create >= 0) {
      (void)H5Pget_nfilters(create);
      H5Pclose(create);
    }
  }
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
}

herr_t visit_attribute(hid_t location, const char* name, const H5A_info_t*, void*) {
  const hid_t attribute = H5Aopen(location, name, H5P_DEFAULT);
  if (attribute >= 0) {
    read_values(attribute, true);
    H5Aclose(attribute);
  }
  return 0;
}

herr_t visit_object(hid_t root, const char* name, const H5O_info_t* info, void*) {
  const hid_t object = H5Oopen(root, name, H5P_DEFAULT);
  if (object < 0) return 0;
  hsize_t index = 0;
  (void)H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_NATIVE, &index, visit_attribute, nullptr);
  if (info != nullptr && info->type == H5O_TYPE_DATASET) read_values(object, false);
  H5Oclose(object);
  return 0;
}

// Everything the readers may decode: each object reachable from the root, its attributes and,
// for a dataset, its description and values. HDF5's refusals are not the probe's business.
void walk_everything(const std::filesystem::path& file) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t handle = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (handle < 0) return;
  (void)H5Ovisit2(handle, H5_INDEX_NAME, H5_ITER_NATIVE, visit_object, nullptr, H5O_INFO_BASIC);
  // Lookups by name take another path through an object's attribute messages than iteration.
  (void)H5Aexists_by_name(handle, "/", "format", H5P_DEFAULT);
  H5Fclose(handle);
}

[[noreturn]] void run_child(const std::filesystem::path& file, detail::Hdf5Walk walk, unsigned seconds) {
  for (const int signal_number : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) {
    ::signal(signal_number, SIG_DFL);
  }
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  // HDF5's complaints and a sanitizer's report inside it are the parent's one-line error.
  const int null_fd = ::open("/dev/null", O_WRONLY);
  if (null_fd >= 0) {
    ::dup2(null_fd, STDERR_FILENO);
    ::dup2(null_fd, STDOUT_FILENO);
  }
  ::alarm(seconds);
  walk(file);
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

void probe_hdf5_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return;  // missing: the reader says so
  detail::probe_in_child(file, walk_everything, kChildSeconds);
}

void detail::probe_in_child(const std::filesystem::path& file, Hdf5Walk walk, unsigned seconds) {
  const pid_t child = ::fork();
  if (child < 0) throw_error(file.string(), ": cannot check the HDF5 file (fork: ", std::strerror(errno), ")");
  if (child == 0) run_child(file, walk, seconds);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw_error(file.string(), ": cannot check the HDF5 file (waitpid: ", std::strerror(errno), ")");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  throw DamagedHdf5File(file.string() + ": damaged HDF5 file: " + describe(status, seconds) + "; not read");
}

}  // namespace hipfai::studies
