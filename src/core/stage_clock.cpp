#include "core/stage_clock.h"

#include <ctime>

namespace pvrt {

double processCpuSeconds() {
  timespec t{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0;
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace pvrt
