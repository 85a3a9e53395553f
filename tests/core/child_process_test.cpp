// Work in a forked child (core/child_process.h): what the parent learns from a child that answers,
// crashes, fails, runs out of time or dies half-way through its answer.
#include "core/child_process.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace hipfai {
namespace {

TEST(ChildProcess, AnAnswerOfAnySizePassesWhole) {
  // More than a pipe holds at once: the parent reads while the child writes.
  std::string big(3 << 20, 'x');
  for (std::size_t i = 0; i < big.size(); i += 4093) big[i] = static_cast<char>('a' + i % 26);
  const ChildOutcome outcome = run_in_child([&](int fd) { if (!write_all(fd, big)) std::_Exit(4); }, {}, "test");
  EXPECT_TRUE(outcome.ok);
  EXPECT_EQ(outcome.answer, big);
  EXPECT_EQ(outcome.failure(0), "");
  EXPECT_EQ(outcome.signal_name(), "");
}

TEST(ChildProcess, DeathsAreReportedAndThisProcessGoesOn) {
  const auto run = [](const std::function<void(int)>& work, unsigned seconds) {
    ChildRequest request;
    request.seconds = seconds;
    return run_in_child(work, request, "test");
  };
  const ChildOutcome segv = run([](int) { std::raise(SIGSEGV); }, 0);
  EXPECT_FALSE(segv.ok);
  EXPECT_EQ(segv.signal_number, SIGSEGV);
  EXPECT_EQ(segv.failure(0), "crashed (SIGSEGV)");
  EXPECT_EQ(run([](int) { std::abort(); }, 0).failure(0), "crashed (SIGABRT)");
  EXPECT_EQ(run([](int) { std::_Exit(3); }, 0).failure(0), "exit status 3");
  EXPECT_EQ(run([](int) { throw std::runtime_error("not caught by the work"); }, 0).failure(0), "exit status 2");
  const ChildOutcome slow = run([](int) { for (;;) ::pause(); }, 1);
  EXPECT_TRUE(slow.timed_out);
  EXPECT_EQ(slow.failure(1), "did not finish within 1 s");
}

// What a child wrote before it died reaches the parent: a caller can tell how far it got
// (geometry/hip_generator.cpp restarts the mesher after the algorithm that crashed).
TEST(ChildProcess, TheAnswerWrittenBeforeACrashIsKept) {
  const ChildOutcome outcome = run_in_child(
      [](int fd) {
        (void)write_all(fd, "step 1;");
        std::abort();
      },
      {}, "test");
  EXPECT_FALSE(outcome.ok);
  EXPECT_EQ(outcome.signal_name(), "SIGABRT");
  EXPECT_EQ(outcome.answer, "step 1;");
}

TEST(ChildProcess, TheChildsStatesStayInTheChild) {
  int value = 1;
  const ChildOutcome outcome = run_in_child([&](int fd) { value = 2; (void)write_all(fd, std::to_string(value)); }, {}, "test");
  EXPECT_EQ(outcome.answer, "2");
  EXPECT_EQ(value, 1);
}

}  // namespace
}  // namespace hipfai
