// hipfai — a progress bar for long runs, written to stderr.
//
// On a terminal it redraws one line ("fai study [#####     ] 12/25  0:41 elapsed, ~1:05 left");
// when stderr is not a terminal (CI, logs) it prints a plain line at every 10 % so logs stay short.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace hipfai {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total, bool enabled = true);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Marks `count` more items done; thread-safe.
  void advance(std::size_t count = 1);
  // Prints the final line (also done by the destructor).
  void finish();

 private:
  void draw(bool final_line);

  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  std::size_t last_decile_ = 0;
  bool enabled_;
  bool tty_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
};

}  // namespace hipfai
