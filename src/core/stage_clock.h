// The wall and CPU time of a stage of a run (load, build, render, write). CPU time is the
// whole process's, every thread's user and system time, so CPU / wall is how many cores the
// stage kept busy on average: a stage that stays near 1 on a machine of many cores is a
// serial stage (issue 24), and this shows it even on a shared machine, where wall times alone
// mislead.
#pragma once

#include <chrono>

namespace pvrt {

struct StageTime {
  double wall = 0, cpu = 0;  // seconds
  double cores() const { return wall > 0 ? cpu / wall : 0; }
};

// This process's CPU time so far, all threads, user and system (CLOCK_PROCESS_CPUTIME_ID).
double processCpuSeconds();

// Started when made; elapsed() is the time since.
class StageClock {
 public:
  StageClock() : wall_(std::chrono::steady_clock::now()), cpu_(processCpuSeconds()) {}
  StageTime elapsed() const {
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_).count(),
            processCpuSeconds() - cpu_};
  }

 private:
  std::chrono::steady_clock::time_point wall_;
  double cpu_;
};

}  // namespace pvrt
