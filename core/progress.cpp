#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace hipfai {

namespace {
std::string format_seconds(double seconds) {
  const auto total = static_cast<long>(seconds + 0.5);
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld", total / 60, total % 60);
  return text;
}
}  // namespace

ProgressBar::ProgressBar(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled && total > 0),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::advance(std::size_t count) {
  std::lock_guard lock(mutex_);
  done_ += count;
  if (done_ > total_) done_ = total_;
  if (!enabled_) return;
  if (tty_) {
    draw(false);
  } else {
    const std::size_t decile = done_ * 10 / total_;
    if (decile != last_decile_) {
      last_decile_ = decile;
      draw(false);
    }
  }
}

void ProgressBar::finish() {
  std::lock_guard lock(mutex_);
  if (finished_ || !enabled_) return;
  finished_ = true;
  // Without a terminal the 100 % line has already been printed by advance().
  if (!tty_ && done_ == total_ && last_decile_ == 10) return;
  draw(true);
}

void ProgressBar::draw(bool final_line) {
  constexpr int kWidth = 30;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = static_cast<double>(done_) / static_cast<double>(total_);
  std::string bar(kWidth, ' ');
  for (int i = 0; i < static_cast<int>(fraction * kWidth); ++i) bar[i] = '#';
  std::string eta;
  if (done_ > 0 && done_ < total_) {
    eta = ", ~" + format_seconds(elapsed / fraction - elapsed) + " left";
  }
  std::fprintf(stderr, "%s%s [%s] %zu/%zu  %s elapsed%s%s", tty_ ? "\r" : "", label_.c_str(),
               bar.c_str(), done_, total_, format_seconds(elapsed).c_str(), eta.c_str(),
               (tty_ && !final_line) ? "\033[K" : "\n");
  std::fflush(stderr);
}

}  // namespace hipfai
