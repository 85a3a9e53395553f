// Cache entries shared by concurrent jobs (core/cache_entry.h, core/file_lock.h): processes and
// threads racing on one entry make it once and leave a whole entry and no temporary or lock file;
// a maker killed with SIGKILL while it holds the lock leaves neither an entry nor a lock, and the
// next maker makes the entry cleanly.
#include "core/cache_entry.h"

#include "core/error.h"
#include "tests/core/scratch_folder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace hipfai {
namespace {

namespace fs = std::filesystem;

bool has_value_file(const fs::path& entry) { return fs::exists(entry / "value"); }

class CacheEntryTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::scratch_folder("cache_entry"); }

  std::string contents(const fs::path& path) const { return test::file_contents(path); }

  // Lines in the counter file: one per fill that ran (appended with O_APPEND, so lines of
  // concurrent writers never mix).
  int fills() const {
    const std::string text = contents(dir_ / "fills.log");
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }

  // A fill that counts itself, takes `ms` and writes the entry's value in two parts (a reader of
  // a half-made entry would see only the first).
  EntryFiller slow_fill(int ms) const {
    const fs::path counter = dir_ / "fills.log";
    return [counter, ms](AtomicDirectory& staging) {
      const int fd = ::open(counter.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (fd >= 0) {
        [[maybe_unused]] const ssize_t written = ::write(fd, "fill\n", 5);
        ::close(fd);
      }
      std::ofstream value(staging.partial_path() / "value");
      value << "first half ";
      value.flush();
      std::this_thread::sleep_for(std::chrono::milliseconds(ms));
      value << "second half";
    };
  }

  // Files other than the entry and the counter: temporaries and lock files left behind.
  std::vector<std::string> leftovers() const {
    std::vector<std::string> names;
    for (const auto& item : fs::directory_iterator(dir_)) {
      const std::string name = item.path().filename().string();
      if (name != "entry" && name != "fills.log") names.push_back(name);
    }
    return names;
  }

  fs::path dir_;
};

TEST_F(CacheEntryTest, ProcessesRacingOnOneEntryMakeItOnce) {
  constexpr int kProcesses = 4;
  const fs::path entry = dir_ / "entry";
  std::vector<pid_t> children;
  for (int p = 0; p < kProcesses; ++p) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      int code = 1;
      try {
        code = 10 + static_cast<int>(make_cache_entry(entry, has_value_file, slow_fill(300)));
      } catch (...) {
      }
      ::_exit(code);
    }
    children.push_back(child);
  }
  int made = 0, elsewhere = 0, found = 0;
  for (const pid_t child : children) {
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    const int code = WEXITSTATUS(status);
    made += code == 10 + static_cast<int>(EntrySource::kMade);
    elsewhere += code == 10 + static_cast<int>(EntrySource::kMadeElsewhere);
    found += code == 10 + static_cast<int>(EntrySource::kFound);
  }
  EXPECT_EQ(made, 1);
  EXPECT_EQ(made + elsewhere + found, kProcesses);  // none failed
  EXPECT_EQ(fills(), 1);                              // the work was done once
  EXPECT_EQ(contents(entry / "value"), "first half second half");
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();
}

TEST_F(CacheEntryTest, ThreadsRacingOnOneEntryMakeItOnce) {
  constexpr int kThreads = 4;
  const fs::path entry = dir_ / "entry";
  std::vector<EntrySource> sources(kThreads, EntrySource::kBusy);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] { sources[static_cast<std::size_t>(t)] = make_cache_entry(entry, has_value_file, slow_fill(200)); });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(std::count(sources.begin(), sources.end(), EntrySource::kMade), 1);
  EXPECT_EQ(std::count(sources.begin(), sources.end(), EntrySource::kBusy), 0);
  EXPECT_EQ(fills(), 1);
  EXPECT_EQ(contents(entry / "value"), "first half second half");
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();
}

TEST_F(CacheEntryTest, TryingWhileAnotherMakesItIsBusyThenFindsItMade) {
  const fs::path entry = dir_ / "entry";
  std::atomic<bool> filling{false};
  std::thread maker([&] {
    make_cache_entry(entry, has_value_file, [&](AtomicDirectory& staging) {
      filling = true;
      slow_fill(400)(staging);
    });
  });
  while (!filling) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(make_cache_entry(entry, has_value_file, slow_fill(0), LockWait::kTry), EntrySource::kBusy);
  maker.join();
  EXPECT_EQ(make_cache_entry(entry, has_value_file, slow_fill(0), LockWait::kTry), EntrySource::kFound);
  EXPECT_EQ(fills(), 1);
}

// The scheduler kills a job while it makes an entry (lock held, temporary folder half written, no
// rename yet): no entry, no lock in the way, and the next maker makes it whole.
TEST_F(CacheEntryTest, AMakerKilledWhileHoldingTheLockLeavesNoEntryAndNoStaleLock) {
  const fs::path entry = dir_ / "entry";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(ready[0]);
    try {
      make_cache_entry(entry, has_value_file, [&](AtomicDirectory& staging) {
        std::ofstream(staging.partial_path() / "value") << "first half ";
        [[maybe_unused]] const ssize_t written = ::write(ready[1], "x", 1);
        for (;;) ::pause();  // killed here
      });
    } catch (...) {
    }
    ::_exit(1);
  }
  ::close(ready[1]);
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  ::close(ready[0]);
  // While the child holds the lock, another maker is kept out.
  EXPECT_EQ(make_cache_entry(entry, has_value_file, slow_fill(0), LockWait::kTry), EntrySource::kBusy);
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_FALSE(fs::exists(entry));                                   // nothing half made under its name
  EXPECT_TRUE(fs::exists(cache_entry_lock_path(entry)));             // its lock file stays, unlocked
  EXPECT_EQ(make_cache_entry(entry, has_value_file, slow_fill(0), LockWait::kTry), EntrySource::kMade);
  EXPECT_EQ(contents(entry / "value"), "first half second half");
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();          // its temporary folder and lock gone
}

TEST_F(CacheEntryTest, AFillThatFailsLeavesNoEntryAndFreesTheLock) {
  const fs::path entry = dir_ / "entry";
  EXPECT_THROW(make_cache_entry(entry, has_value_file, [](AtomicDirectory&) { throw_error("the run failed"); }), Error);
  EXPECT_FALSE(fs::exists(entry));
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();
  EXPECT_EQ(make_cache_entry(entry, has_value_file, slow_fill(0), LockWait::kTry), EntrySource::kMade);
}

TEST_F(CacheEntryTest, AWaiterWhoseLockFileWasRemovedLocksTheNewOne) {
  const fs::path path = dir_ / "x.lock";
  std::atomic<bool> second_held{false};
  std::thread second;
  {
    const FileLock first(path, LockWait::kBlock);
    ASSERT_EQ(first.state(), LockState::kHeld);
    second = std::thread([&] {
      const FileLock lock(path, LockWait::kBlock);  // waits on the first one's file
      second_held = lock.state() == LockState::kHeld;
      // Held on the file under the name, so a third locker is kept out.
      const FileLock third(path, LockWait::kTry);
      second_held = second_held && third.state() == LockState::kBusy;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_FALSE(second_held);
  }  // released: its file removed
  second.join();
  EXPECT_TRUE(second_held);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace hipfai
