// HDF5 decoding in a child process (studies/results/hdf5_child.h) and the reader built on it
// (studies/results/results_file.h): sound files are read, values and errors alike come back through the
// pipe, a child that dies is a one-line refusal while this process goes on, and the files found by
// fuzzing to crash HDF5 (tests/data/hdf5-crashes/) never take this process down.
#include "core/error.h"
#include "studies/estimator_model_file.h"
#include "studies/results/hdf5_child.h"
#include "studies/results/results_file.h"

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

fs::path hdf5_scratch_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hipfai_hdf5_child_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string message_of(const std::function<void()>& read) {
  try {
    read();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(Hdf5Child, SoundFileIsReadValuesAndErrorsAlike) {
  const fs::path file = hdf5_scratch_file("sound.h5");
  {
    ResultsFile out(file);
    out.write("/steps/angle_deg", {0.0, 1.5, 3.0}, 1, "deg");
    out.write("/steps/rotation", std::vector<double>(18, 0.25), 9, "1");
    out.write("/empty", {}, 1, "1");
    out.set_attribute("/", "code_version", "test");
    out.commit();
  }
  ResultsReader reader(file);
  reader.prefetch({"/steps/angle_deg", "/missing", "/steps/rotation", "/empty"},
                  {{"/", "code_version"}, {"/", "nothing"}});
  std::size_t rows = 0, cols = 0;
  EXPECT_EQ(reader.dataset("/steps/angle_deg", &rows, &cols), (std::vector<double>{0.0, 1.5, 3.0}));
  EXPECT_EQ(rows, 3u);
  EXPECT_EQ(cols, 1u);
  EXPECT_EQ(reader.dataset("/steps/rotation", &rows, &cols).size(), 18u);
  EXPECT_EQ(rows, 2u);
  EXPECT_EQ(cols, 9u);
  EXPECT_TRUE(reader.dataset("/empty").empty());
  EXPECT_EQ(reader.string_attribute("/", "code_version"), "test");
  EXPECT_EQ(message_of([&] { (void)reader.dataset("/missing"); }), file.string() + ": no dataset /missing");
  EXPECT_EQ(message_of([&] { (void)reader.string_attribute("/", "nothing"); }),
            file.string() + ": no attribute nothing on /");
  // Not prefetched: read in a child of its own, the same answer.
  EXPECT_EQ(read_dataset(file, "/steps/angle_deg"), (std::vector<double>{0.0, 1.5, 3.0}));
  EXPECT_EQ(read_string_attribute(file, "/", "code_version"), "test");
  fs::remove_all(file.parent_path());
}

TEST(Hdf5Child, FilesHdf5RefusesAreTheReadersErrors) {
  const fs::path text = hdf5_scratch_file("text.h5");
  std::ofstream(text) << "not HDF5\n";
  for (const fs::path& file : {text, hdf5_scratch_file("missing.h5")}) {
    try {
      (void)read_dataset(file, "/x");
      ADD_FAILURE() << file << " was read";
    } catch (const DamagedHdf5File& error) {
      ADD_FAILURE() << file << " reported as damaged HDF5: " << error.what();
    } catch (const Error& error) {
      EXPECT_EQ(std::string(error.what()), file.string() + ": cannot open HDF5 file");
    }
  }
  fs::remove_all(text.parent_path());
}

// The mechanism, whatever this build's heap does with HDF5's over-reads: a child that dies by a
// signal, by a sanitizer-style abort, with an error status or by running out of time is a
// one-line refusal, and this process goes on; a child that exits normally hands over its bytes.
TEST(Hdf5Child, AChildThatDiesIsAOneLineRefusal) {
  const fs::path file = "/some/where/any.h5";
  const auto refusal = [&](const std::function<void(int)>& work, unsigned seconds) -> std::string {
    try {
      (void)detail::run_in_child(file, work, seconds);
    } catch (const DamagedHdf5File& error) {
      return error.what();
    }
    return "";
  };
  const std::string prefix = file.string() + ": damaged HDF5 file: ";
  EXPECT_EQ(refusal([](int) { std::raise(SIGSEGV); }, 60),
            prefix + "the HDF5 library crashed decoding it (SIGSEGV); not read");
  EXPECT_EQ(refusal([](int) { std::abort(); }, 60), prefix + "the HDF5 library crashed decoding it (SIGABRT); not read");
  EXPECT_EQ(refusal([](int) { std::_Exit(3); }, 60),
            prefix + "the HDF5 library failed decoding it (exit status 3); not read");
  EXPECT_EQ(refusal([](int) { throw std::runtime_error("x"); }, 60),
            prefix + "the HDF5 library failed decoding it (exit status 2); not read");
  EXPECT_EQ(refusal([](int) { for (;;) ::pause(); }, 1), prefix + "HDF5 did not finish decoding it within 1 s; not read");
  // More than a pipe holds at once: the parent reads while the child writes.
  const std::string big(1 << 20, 'x');
  EXPECT_EQ(detail::run_in_child(file, [&](int fd) { (void)!::write(fd, big.data(), big.size()); }, 60), big);
}

// Files found by fuzzing on which HDF5 1.10.8 reads past its buffers or uses freed memory (kept in
// tests/data/hdf5-crashes/; also seeds of the HDF5 fuzz harnesses, which replay them under ASan).
// Whether HDF5 crashes on one depends on the allocator and the order of the calls: refused as
// damaged, or answered with a one-line error or a value; never taking this process down.
TEST(Hdf5Child, FilesThatCrashHdf5AreRefusedOrReadWithoutHarm) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(fs::path(HIPFAI_SOURCE_DIR) / "tests/data/hdf5-crashes")) {
    files.push_back(entry.path());
  }
  ASSERT_FALSE(files.empty());
  for (const fs::path& file : files) {
    try {
      ResultsReader reader(file);
      reader.prefetch({"/steps/rotation", "/total"}, {{"/", "code_version"}, {"/steps/rotation", "units"}});
    } catch (const DamagedHdf5File& error) {
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
    EXPECT_THROW((void)read_estimator_model(file), Error) << file;
  }
}

}  // namespace
}  // namespace hipfai::studies
