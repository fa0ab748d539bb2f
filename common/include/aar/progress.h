#pragma once
// A progress line on stderr: items done of total, rate and ETA. Redraws in
// place on a terminal, prints at most every `interval_s` otherwise (logs).
// Also the stage timer the tools' per-stage times use.

#include <chrono>
#include <cstddef>
#include <string>

namespace aar {

/// Wall time since `start` [ms].
inline double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

class Progress {
 public:
  Progress(std::string label, size_t total, double interval_s = 2.0);
  /// Marks `n` more items done and prints if due.
  void Advance(size_t n = 1);
  /// Prints the final line with the total time.
  void Finish();

 private:
  void Print(bool final_line);
  std::string label_;
  size_t total_;
  size_t done_ = 0;
  double interval_s_;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace aar
