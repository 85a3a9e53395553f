// The HDF5 probe (studies/hdf5_probe.h) and the reader it guards (studies/results_file.h):
// sound files pass and are read through one open handle; files that crash HDF5 itself (found by
// fuzzing, kept in tests/data/hdf5-crashes/) are refused with a one-line error while this
// process goes on; files HDF5 merely refuses are left to the reader's own messages.
#include "core/error.h"
#include "studies/estimator_study.h"
#include "studies/hdf5_probe.h"
#include "studies/results_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hipfai_hdf5_probe_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::vector<fs::path> crashing_files() {
  std::vector<fs::path> files;
  const fs::path dir = fs::path(HIPFAI_SOURCE_DIR) / "tests/data/hdf5-crashes";
  for (const auto& entry : fs::directory_iterator(dir)) files.push_back(entry.path());
  return files;
}

TEST(Hdf5Probe, SoundFilePassesAndIsReadThroughOneHandle) {
  const fs::path file = scratch("sound.h5");
  {
    ResultsFile out(file);
    out.write("/steps/angle_deg", {0.0, 1.5, 3.0}, 1, "deg");
    out.write("/steps/rotation", std::vector<double>(18, 0.25), 9, "1");
    out.set_attribute("/", "code_version", "test");
    out.commit();
  }
  EXPECT_NO_THROW(probe_hdf5_file(file));
  const ResultsReader reader(file);
  std::size_t rows = 0, cols = 0;
  EXPECT_EQ(reader.dataset("/steps/angle_deg", &rows, &cols), (std::vector<double>{0.0, 1.5, 3.0}));
  EXPECT_EQ(rows, 3u);
  EXPECT_EQ(reader.dataset("/steps/rotation", &rows, &cols).size(), 18u);
  EXPECT_EQ(cols, 9u);
  EXPECT_EQ(reader.string_attribute("/", "code_version"), "test");
  EXPECT_THROW((void)reader.dataset("/missing"), Error);
  fs::remove_all(file.parent_path());
}

TEST(Hdf5Probe, FilesHdf5RefusesAreLeftToTheReader) {
  const fs::path text = scratch("text.h5");
  std::ofstream(text) << "not HDF5\n";
  EXPECT_NO_THROW(probe_hdf5_file(text));
  EXPECT_NO_THROW(probe_hdf5_file(scratch("missing.h5")));
  try {
    const ResultsReader reader(text);
    ADD_FAILURE() << "a text file was opened as HDF5";
  } catch (const DamagedHdf5File& error) {
    ADD_FAILURE() << "a text file reported as damaged HDF5: " << error.what();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("cannot open HDF5 file"), std::string::npos) << error.what();
  }
  fs::remove_all(text.parent_path());
}

// The mechanism, whatever this build's heap does with HDF5's over-reads: a child that dies by a
// signal, by a sanitizer-style abort, with an error status or by running out of time is a
// one-line refusal, and this process goes on.
void crash_by_segv(const fs::path&) { std::raise(SIGSEGV); }
void crash_by_abort(const fs::path&) { std::abort(); }
void fail_with_status(const fs::path&) { std::_Exit(3); }
void hang(const fs::path&) {
  for (;;) ::pause();
}
void succeed(const fs::path&) {}

TEST(Hdf5Probe, AChildThatDiesIsAOneLineRefusal) {
  const fs::path file = scratch("any.h5");
  std::ofstream(file) << "bytes";
  const auto refusal = [&](detail::Hdf5Walk walk, unsigned seconds) -> std::string {
    try {
      detail::probe_in_child(file, walk, seconds);
    } catch (const DamagedHdf5File& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_EQ(refusal(crash_by_segv, 60), file.string() + ": damaged HDF5 file: the HDF5 library crashed decoding it (SIGSEGV); not read");
  EXPECT_EQ(refusal(crash_by_abort, 60), file.string() + ": damaged HDF5 file: the HDF5 library crashed decoding it (SIGABRT); not read");
  EXPECT_EQ(refusal(fail_with_status, 60), file.string() + ": damaged HDF5 file: the HDF5 library failed decoding it (exit status 3); not read");
  EXPECT_EQ(refusal(hang, 1), file.string() + ": damaged HDF5 file: HDF5 did not finish decoding it within 1 s; not read");
  EXPECT_EQ(refusal(succeed, 60), "");
  fs::remove_all(file.parent_path());
}

// Files found by fuzzing on which HDF5 1.10.8 reads past its buffers (kept in
// tests/data/hdf5-crashes/). Under AddressSanitizer (the fuzz build) each crashes HDF5 and must be
// refused; in an ordinary build the over-read may pass unnoticed, and then the readers must still
// answer with a one-line error or a value — never take this process down.
TEST(Hdf5Probe, FilesThatCrashHdf5AreRefusedOrReadWithoutHarm) {
  const std::vector<fs::path> files = crashing_files();
  ASSERT_FALSE(files.empty());
#if defined(__SANITIZE_ADDRESS__)
  constexpr bool kMustRefuse = true;
#else
  constexpr bool kMustRefuse = false;
#endif
  for (const fs::path& file : files) {
    bool refused = false;
    try {
      probe_hdf5_file(file);
    } catch (const DamagedHdf5File& error) {
      refused = true;
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
    EXPECT_TRUE(refused || !kMustRefuse) << file;
    try {
      const ResultsReader reader(file);
      (void)reader.string_attribute("/", "code_version");
    } catch (const Error& error) {
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
    EXPECT_THROW((void)read_estimator_model(file), Error) << file;
  }
}

}  // namespace
}  // namespace hipfai::studies
