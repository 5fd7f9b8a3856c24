#include "parallel/threads.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <thread>

#if defined(__linux__)
#include <sched.h>
#endif

namespace pvrt {

namespace {
std::atomic<int> gBudget{0};
std::atomic<int> gSlot{0}, gSlots{1};
std::atomic<int> gSharers{1};  // the processes of the share as set, kept when pinning ends it
#if defined(__linux__)
cpu_set_t gStartMask;  // the mask before pinProcessToShare narrowed it
std::atomic<bool> gNarrowed{false};
#endif
}  // namespace

std::vector<int> allowedCpus() {
  std::vector<int> cpus;
#if defined(__linux__)
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0)
    for (int c = 0; c < CPU_SETSIZE; ++c)
      if (CPU_ISSET(c, &allowed)) cpus.push_back(c);
#endif
  if (cpus.empty())
    for (unsigned c = 0; c < std::max(1u, std::thread::hardware_concurrency()); ++c) cpus.push_back(int(c));
  return cpus;
}

void setCpuShare(CpuShare share) {
  gSlots = std::max(1, share.slots);
  gSlot = std::clamp(share.slot, 0, gSlots - 1);
  if (gSlots > 1) gSharers = gSlots.load();
}

CpuShare cpuShare() { return {gSlot.load(), gSlots.load()}; }

void setThreadBudget(int threads) { gBudget = std::max(0, threads); }

int threadsFromEnvironment() {
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (!env || !*env) return 0;
  // OpenMP allows a list, one count per nesting level ("4,2"): the first is ours.
  const char* p = env;
  while (*p == ' ') ++p;
  long n = 0;
  bool digits = false;
  for (; *p >= '0' && *p <= '9'; ++p, digits = true) n = std::min(n * 10 + (*p - '0'), long(kMaxThreads) + 1);
  while (*p == ' ') ++p;
  if (!digits || (*p && *p != ',') || n < 1 || n > kMaxThreads) return -1;
  return int(n);
}

int threadBudget() {
  if (const int set = gBudget.load(); set > 0) return set;
  if (const int env = threadsFromEnvironment(); env > 0) return env;
  return std::max(1, int(allowedCpus().size()) / gSlots.load());
}

bool pinningAllowed() {
  const char* pin = std::getenv("PVRT_PIN_THREADS");
  return !(pin && std::strcmp(pin, "0") == 0) && !std::getenv("OMP_PROC_BIND") && !std::getenv("OMP_PLACES") &&
         !std::getenv("GOMP_CPU_AFFINITY");
}

bool pinProcessToShare() {
#if defined(__linux__)
  const CpuShare share = cpuShare();
  if (share.slots <= 1 || !pinningAllowed()) return false;
  const std::vector<int> cpus = allowedCpus();
  const size_t width = size_t(threadBudget());
  if (size_t(share.slots) * width > cpus.size()) return false;
  cpu_set_t mine;
  CPU_ZERO(&mine);
  for (size_t k = 0; k < width; ++k) CPU_SET(cpus[size_t(share.slot) * width + k], &mine);
  if (sched_getaffinity(0, sizeof gStartMask, &gStartMask) != 0) return false;
  if (sched_setaffinity(0, sizeof mine, &mine) != 0) return false;
  gNarrowed = true;
  setCpuShare({});
  return true;
#else
  return false;
#endif
}

int takeWholeShare() {
  const int sharers = gSharers.exchange(1);
  if (sharers <= 1) return threadBudget();
  const int together = threadBudget() * sharers;
#if defined(__linux__)
  // The calling thread's mask; threads started after this inherit it.
  if (gNarrowed.exchange(false)) (void)sched_setaffinity(0, sizeof gStartMask, &gStartMask);
#endif
  setCpuShare({});
  setThreadBudget(std::min(together, int(allowedCpus().size())));
  return threadBudget();
}

}  // namespace pvrt
