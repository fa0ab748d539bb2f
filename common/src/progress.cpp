#include "aar/progress.h"

#include <unistd.h>

#include <cstdio>

namespace aar {

Progress::Progress(std::string label, size_t total, double interval_s)
    : label_(std::move(label)),
      total_(total),
      interval_s_(interval_s),
      tty_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

void Progress::Advance(size_t n) {
  done_ += n;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (since >= (tty_ ? 0.25 : interval_s_) || done_ == total_) {
    last_print_ = now;
    Print(false);
  }
}

void Progress::Finish() { Print(true); }

void Progress::Print(bool final_line) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done_) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total_ - done_) / rate : 0.0;
  if (final_line) {
    std::fprintf(stderr, "%s%s: %zu/%zu done in %.1f s (%.2f/s)\n", tty_ ? "\r\033[K" : "", label_.c_str(), done_,
                 total_, elapsed, rate);
  } else {
    std::fprintf(stderr, "%s%s: %zu/%zu (%.0f%%) %.2f/s, ETA %.0f s%s", tty_ ? "\r\033[K" : "", label_.c_str(), done_,
                 total_, total_ ? 100.0 * static_cast<double>(done_) / static_cast<double>(total_) : 100.0, rate, eta,
                 tty_ ? "" : "\n");
  }
  std::fflush(stderr);
}

}  // namespace aar
