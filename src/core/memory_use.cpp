#include "core/memory_use.h"

#include <sys/resource.h>

namespace pvrt {

size_t peakResidentBytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return size_t(u.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace pvrt
