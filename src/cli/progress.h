// A one-line progress bar with ETA on stderr, shown only when stderr is a terminal.
#pragma once

#include <chrono>

namespace pvrt::cli {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  void update(long done, long total);
  void finish();

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
  bool drawn_ = false;
};

}  // namespace pvrt::cli
