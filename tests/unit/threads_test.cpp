// The thread budget of MPI ranks that share a node's CPUs, and rank 0 taking them all back
// for its write stage once the others are done (takeWholeShare). Each test case runs in a
// process of its own (gtest_discover_tests), so the process-wide budget and mask it sets
// touch no other case.
#include "parallel/threads.h"

#include <gtest/gtest.h>

#include <sched.h>

#include <algorithm>
#include <cstdlib>

namespace pvrt {
namespace {

int maskSize() {
  cpu_set_t m;
  CPU_ZERO(&m);
  sched_getaffinity(0, sizeof m, &m);
  return CPU_COUNT(&m);
}

TEST(Threads, TheWholeShareHasAsManyThreadsAsItsSharersTogether) {
  const int cpus = int(allowedCpus().size());
  setThreadBudget(1);  // --threads 1: each of the two ranks renders on one thread
  setCpuShare({1, 2});
  EXPECT_EQ(threadBudget(), 1);
  EXPECT_EQ(takeWholeShare(), std::min(2, cpus));
  EXPECT_EQ(cpuShare().slots, 1);
  EXPECT_EQ(takeWholeShare(), std::min(2, cpus)) << "a second call takes nothing more";
}

TEST(Threads, TheWholeShareNeverHasMoreThreadsThanCpus) {
  const int cpus = int(allowedCpus().size());
  setThreadBudget(cpus);  // each of three sharers asked for every CPU
  setCpuShare({0, 3});
  EXPECT_EQ(takeWholeShare(), cpus);
}

TEST(Threads, WithoutSharersNothingChanges) {
  setThreadBudget(1);
  EXPECT_EQ(takeWholeShare(), 1);
}

TEST(Threads, TheWholeShareGivesBackTheMaskPinningNarrowed) {
  const int cpus = maskSize();
  if (cpus < 2) GTEST_SKIP() << "needs two CPUs";
  if (!pinningAllowed()) GTEST_SKIP() << "pinning is left to the user here";
  setThreadBudget(0);
  setCpuShare({1, 2});
  ASSERT_TRUE(pinProcessToShare());
  EXPECT_EQ(maskSize(), cpus / 2) << "pinned to its half";
  EXPECT_EQ(threadBudget(), cpus / 2);
  EXPECT_EQ(takeWholeShare(), 2 * (cpus / 2));
  EXPECT_EQ(maskSize(), cpus) << "the mask it started with";
}

}  // namespace
}  // namespace pvrt
