#include "cli/huge_pages.h"

#include <cstdlib>
#include <cstring>
#include <string>

#if defined(__linux__) && defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>
#endif

namespace pvrt::cli {

void restartWithHugePages(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  const char* off = std::getenv("PVRT_HUGE_PAGES");
  if (off && std::strcmp(off, "0") == 0) return;
  // libgomp binds the initial thread to its first place before main() when asked to bind,
  // and the restarted program would inherit that one-CPU mask: no restart then.
  const char* bind = std::getenv("OMP_PROC_BIND");
  if ((bind && std::strcmp(bind, "false") != 0 && std::strcmp(bind, "FALSE") != 0) || std::getenv("OMP_PLACES") ||
      std::getenv("GOMP_CPU_AFFINITY"))
    return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;  // set already (by us or the user)
  const std::string value = tunables && *tunables ? std::string(tunables) + ":glibc.malloc.hugetlb=1"
                                                  : std::string("glibc.malloc.hugetlb=1");
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Only reached when the restart failed: go on with small pages.
#else
  (void)argv;
#endif
}

void keepHeapTop() {
#if defined(__linux__) && defined(__GLIBC__)
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables &&
      (std::strstr(tunables, "glibc.malloc.top_pad") || std::strstr(tunables, "glibc.malloc.trim_threshold")))
    return;
  (void)mallopt(M_TOP_PAD, 64 << 20);
#endif
}

}  // namespace pvrt::cli
