// The parallel seam: every item rendered once, and the CPU pinning of a render's threads
// confined to the render (the caller's own CPU mask is the same afterwards).
#include "parallel/parallel_for.h"
#include "parallel/permute.h"

#include <gtest/gtest.h>

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <random>
#include <set>
#include <string>
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

int threadsOfThisProcess() {
  int n = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) n += task.is_directory();
  return n;
}

// An MPI rank done with its work ends the threads OpenMP keeps waiting after a region, so
// that they spin on no CPU rank 0's write could use; a later region starts them again.
TEST(ParallelFor, IdleThreadsCanBeEnded) {
  releaseIdleThreads();  // those an earlier test in this process left (the binary run whole)
  const int alone = threadsOfThisProcess();
  std::atomic<int> ran{0};
  parallelIndices(4, 2, [&](size_t) { ++ran; });
  EXPECT_EQ(ran.load(), 4);
  ASSERT_GT(threadsOfThisProcess(), alone) << "OpenMP kept no thread after the region";
  releaseIdleThreads();
  EXPECT_EQ(threadsOfThisProcess(), alone);
  parallelIndices(4, 2, [&](size_t) { ++ran; });
  EXPECT_EQ(ran.load(), 8);
}

// permuteInPlace gives what a copy gathered slot by slot gives, on any number of threads,
// for permutations of short cycles, one long cycle, fixed points, and a mix.
TEST(PermuteInPlace, GivesTheGatheredOrder) {
  const size_t n = 50000;
  std::vector<std::vector<uint32_t>> orders;
  std::vector<uint32_t> identity(n);
  for (uint32_t i = 0; i < n; ++i) identity[i] = i;
  orders.push_back(identity);
  std::vector<uint32_t> swaps = identity;  // cycles of two
  for (size_t i = 0; i + 1 < n; i += 2) std::swap(swaps[i], swaps[i + 1]);
  orders.push_back(swaps);
  std::vector<uint32_t> rotate(n);  // one cycle of every slot
  for (uint32_t i = 0; i < n; ++i) rotate[i] = uint32_t((i + 7) % n);
  orders.push_back(rotate);
  std::vector<uint32_t> shuffled = identity;  // a few long cycles and some short ones
  std::mt19937 rng(5);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  orders.push_back(shuffled);
  for (const auto& order : orders) {
    std::vector<std::string> want(n);
    for (size_t j = 0; j < n; ++j) want[j] = "item " + std::to_string(order[j]);
    for (int threads : {1, 3, 8}) {
      std::vector<std::string> a(n);
      for (size_t i = 0; i < n; ++i) a[i] = "item " + std::to_string(i);
      permuteInPlace(a, order, threads);
      ASSERT_EQ(a, want) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace pvrt
