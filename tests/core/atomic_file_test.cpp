#include "core/atomic_file.h"

#include "core/error.h"
#include "tests/core/scratch_folder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <sys/wait.h>
#include <unistd.h>

namespace hipfai {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::scratch_folder("atomic_file"); }

  std::string contents(const fs::path& path) const { return test::file_contents(path); }

  std::size_t files_in_dir() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, BytesArriveWhole) {
  // Includes a NUL and a CR LF pair: the content goes out in binary, unchanged.
  const std::string bytes("a\0b\r\nc", 6);
  write_file_atomically(dir_ / "out.bin", bytes);
  EXPECT_EQ(contents(dir_ / "out.bin"), bytes);
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(AtomicFileTest, ReplacesAnExistingFile) {
  write_file_atomically(dir_ / "out.txt", std::string("old"));
  write_file_atomically(dir_ / "out.txt", [](std::ostream& out) { out << "new " << 42; });
  EXPECT_EQ(contents(dir_ / "out.txt"), "new 42");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(AtomicFileTest, AWriterThatThrowsLeavesTheOldFileAndNoTemporary) {
  write_file_atomically(dir_ / "out.txt", std::string("old"));
  EXPECT_THROW(write_file_atomically(dir_ / "out.txt",
                                     [](std::ostream& out) {
                                       out << "half of the new content";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  EXPECT_EQ(contents(dir_ / "out.txt"), "old");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(AtomicFileTest, UncommittedFileIsRemoved) {
  fs::path partial;
  {
    AtomicFile file(dir_ / "never.txt");
    partial = file.partial_path();
    std::ofstream(partial) << "abandoned";
    EXPECT_TRUE(fs::exists(partial));
  }
  EXPECT_FALSE(fs::exists(partial));
  EXPECT_FALSE(fs::exists(dir_ / "never.txt"));
}

TEST_F(AtomicFileTest, TwoWritesOfOneTargetUseDifferentTemporaries) {
  // Processes (and threads) sharing a cache may write the same target at once.
  const AtomicFile first(dir_ / "same.bin");
  const AtomicFile second(dir_ / "same.bin");
  EXPECT_NE(first.partial_path(), second.partial_path());
  EXPECT_EQ(first.partial_path().parent_path(), dir_);
  EXPECT_EQ(first.partial_path().extension(), ".partial");
}

TEST_F(AtomicFileTest, MissingFolderIsAOneLineErrorNamingTheTarget) {
  const fs::path path = dir_ / "no" / "such" / "folder.txt";
  try {
    write_file_atomically(path, std::string("x"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path.string() + ": cannot write", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(AtomicFileTest, CommitOntoADirectoryFailsAndCleansUp) {
  fs::create_directories(dir_ / "taken" / "inside");
  try {
    write_file_atomically(dir_ / "taken", std::string("x"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot move the written file into place"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(files_in_dir(), 1u);  // the directory only, no temporary beside it
}


// ---- folders

bool has_done_file(const fs::path& dir) { return fs::exists(dir / "done"); }

TEST_F(AtomicFileTest, FolderArrivesWholeAndUncommittedOneIsRemoved) {
  {
    AtomicDirectory folder(dir_ / "entry");
    write_file_atomically(folder.partial_path() / "done", std::string("1"));
    EXPECT_FALSE(fs::exists(dir_ / "entry"));  // nothing under the target's name until commit
    EXPECT_TRUE(folder.commit(has_done_file));
  }
  EXPECT_EQ(contents(dir_ / "entry" / "done"), "1");
  {
    AtomicDirectory abandoned(dir_ / "other");
    std::ofstream(abandoned.partial_path() / "half") << "interrupted";
  }
  EXPECT_EQ(files_in_dir(), 1u);  // "entry" only: the abandoned folder went with its content
}

TEST_F(AtomicFileTest, FolderFinishedFirstElsewhereIsKeptAndAnIncompleteOneReplaced) {
  fs::create_directories(dir_ / "entry");
  write_file_atomically(dir_ / "entry" / "done", std::string("theirs"));
  {
    AtomicDirectory late(dir_ / "entry");
    write_file_atomically(late.partial_path() / "done", std::string("ours"));
    EXPECT_FALSE(late.commit(has_done_file));
  }
  EXPECT_EQ(contents(dir_ / "entry" / "done"), "theirs");
  EXPECT_EQ(files_in_dir(), 1u);

  fs::create_directories(dir_ / "broken");
  std::ofstream(dir_ / "broken" / "half") << "left by a killed run";
  AtomicDirectory fresh(dir_ / "broken");
  write_file_atomically(fresh.partial_path() / "done", std::string("new"));
  EXPECT_TRUE(fresh.commit(has_done_file));
  EXPECT_EQ(contents(dir_ / "broken" / "done"), "new");
  EXPECT_FALSE(fs::exists(dir_ / "broken" / "half"));
}

TEST_F(AtomicFileTest, FoldersOfDeadProcessesAreRemovedByTheNextRun) {
  // 2147483646 exceeds Linux's largest pid (2^22), so no process has it.
  const fs::path dead = dir_ / "entry.2147483646-0.partial";
  const fs::path live = dir_ / ("entry." + std::to_string(::getpid()) + "-999.partial");
  const fs::path other = dir_ / "other.2147483646-0.partial";
  for (const fs::path& folder : {dead, live, other}) fs::create_directories(folder / "sub");
  const AtomicDirectory next(dir_ / "entry");
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));   // this process's own
  EXPECT_TRUE(fs::exists(other));  // another target's
}

// A cache on a network filesystem is shared by machines: a temporary named by another machine
// ("@<host>") belongs to a process this one cannot look at, and is left alone even when the same
// pid runs nothing here. This machine's own (its name as partial_path() spells it) are cleaned.
TEST_F(AtomicFileTest, FoldersOfOtherMachinesAreLeftAlone) {
  const AtomicDirectory probe(dir_ / "probe");
  const std::string own = probe.partial_path().filename().string();
  const std::string this_host = own.substr(own.find('@') + 1, own.size() - own.find('@') - 1 - 8);
  const fs::path elsewhere = dir_ / "entry.2147483646-0@some-other-node.partial";
  const fs::path here = dir_ / ("entry.2147483646-1@" + this_host + ".partial");
  for (const fs::path& folder : {elsewhere, here}) fs::create_directories(folder);
  const AtomicDirectory next(dir_ / "entry");
  EXPECT_TRUE(fs::exists(elsewhere));
  EXPECT_FALSE(fs::exists(here));
}

// A writer killed mid-write leaves "<target>.<pid>-<n>.partial" beside the target (a generated hip's
// folder is written file by file); the next write of that target removes it, and only it.
TEST_F(AtomicFileTest, FilesOfDeadProcessesAreRemovedByTheNextWrite) {
  const fs::path dead = dir_ / "mesh.ply.2147483646-3.partial";
  const fs::path live = dir_ / ("mesh.ply." + std::to_string(::getpid()) + "-999.partial");
  const fs::path other = dir_ / "mesh.ply.json.2147483646-0.partial";
  for (const fs::path& file : {dead, live, other}) std::ofstream(file) << "half";
  write_file_atomically(dir_ / "mesh.ply", std::string_view("whole"));
  EXPECT_EQ(contents(dir_ / "mesh.ply"), "whole");
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));   // this process's own
  EXPECT_TRUE(fs::exists(other));  // another target's
}

// A process killed with its parent can stay a zombie where nothing reaps it (PID 1 of a container):
// it exists for kill(pid, 0) but will never finish its folder, which the next run must remove.
TEST_F(AtomicFileTest, FoldersOfZombieProcessesAreRemovedByTheNextRun) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  // Not reaped yet: a zombie once it has exited.
  for (int wait_ms = 0; wait_ms < 5000; wait_ms += 10) {
    std::ifstream stat("/proc/" + std::to_string(child) + "/stat");
    std::string line;
    std::getline(stat, line);
    if (line.find(") Z") != std::string::npos) break;
    ::usleep(10000);
  }
  const fs::path zombie = dir_ / ("entry." + std::to_string(child) + "-0.partial");
  fs::create_directories(zombie);
  const AtomicDirectory next(dir_ / "entry");
  EXPECT_FALSE(fs::exists(zombie));
  ::waitpid(child, nullptr, 0);
}

TEST_F(AtomicFileTest, KeptFolderStaysForItsLog) {
  fs::path partial;
  {
    AtomicDirectory failed(dir_ / "entry");
    partial = failed.partial_path();
    std::ofstream(partial / "run.log") << "why it failed";
    failed.keep();
  }
  EXPECT_EQ(contents(partial / "run.log"), "why it failed");
  EXPECT_FALSE(fs::exists(dir_ / "entry"));
  fs::remove_all(partial);
}

}  // namespace
}  // namespace hipfai
