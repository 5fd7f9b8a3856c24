// The parallel seam: every item rendered once, and the CPU pinning of a render's threads
// confined to the render (the caller's own CPU mask is the same afterwards).
#include "parallel/parallel_for.h"

#include <gtest/gtest.h>

#include <sched.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <set>
#include <vector>

namespace pvrt {
namespace {

cpu_set_t currentMask() {
  cpu_set_t m;
  CPU_ZERO(&m);
  sched_getaffinity(0, sizeof m, &m);
  return m;
}

TEST(ParallelFor, EveryItemOnceOnEveryStrategy) {
  for (Strategy st : {Strategy::Block, Strategy::Cyclic, Strategy::Dynamic, Strategy::Tiles}) {
    const WorkPlan plan = makeWorkPlan({st, 0, 8}, 50, 30, 2);
    std::vector<std::atomic<int>> seen(plan.items.size());
    parallelFor(Backend::OpenMP, 2, plan, [&](size_t i, int worker) {
      EXPECT_TRUE(worker == 0 || worker == 1);
      ++seen[i];
    });
    for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i].load(), 1) << strategyName(st) << " item " << i;
  }
}

TEST(ParallelFor, ThreadsArePinnedOnlyDuringTheRender) {
  const cpu_set_t before = currentMask();
  if (CPU_COUNT(&before) < 2) GTEST_SKIP() << "needs two CPUs";
  const WorkPlan plan = makeWorkPlan({Strategy::Tiles, 0, 4}, 64, 64, 2);
  std::mutex m;
  std::set<int> cpusOfWorkers[2];
  std::vector<int> maskSizes;
  parallelFor(Backend::OpenMP, 2, plan, [&](size_t, int worker) {
    const cpu_set_t mask = currentMask();
    std::lock_guard<std::mutex> lock(m);
    maskSizes.push_back(CPU_COUNT(&mask));
    for (int c = 0; c < CPU_SETSIZE; ++c)
      if (CPU_ISSET(c, &mask)) cpusOfWorkers[worker].insert(c);
  });
  const cpu_set_t after = currentMask();
  EXPECT_TRUE(CPU_EQUAL(&before, &after)) << "the calling thread's CPU mask changed";
  if (std::getenv("OMP_PROC_BIND") || std::getenv("OMP_PLACES") || std::getenv("GOMP_CPU_AFFINITY") ||
      std::getenv("PVRT_PIN_THREADS") || std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE"))
    return;  // pinning is left to the user then
  for (int s : maskSizes) EXPECT_EQ(s, 1) << "a worker ran on more than one CPU";
  if (!cpusOfWorkers[0].empty() && !cpusOfWorkers[1].empty()) {
    EXPECT_EQ(cpusOfWorkers[0].size(), 1u);
    EXPECT_EQ(cpusOfWorkers[1].size(), 1u);
    EXPECT_NE(*cpusOfWorkers[0].begin(), *cpusOfWorkers[1].begin()) << "both workers on one CPU";
  }
}

}  // namespace
}  // namespace pvrt
