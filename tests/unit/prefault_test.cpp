// prefaultAsync maps memory in ahead of its writer and must never change what it holds:
// the loader fills the memory while the faults are under way.
#include "core/prefault.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace pvrt {
namespace {

TEST(Prefault, KeepsWhatTheMemoryHolds) {
  std::vector<uint8_t> bytes(size_t(9) << 20);  // several pages, not page-aligned at either end
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(i * 131 + 7);
  std::future<void> done = prefaultAsync(bytes.data() + 3, bytes.size() - 5, 0);
  if (done.valid()) done.wait();  // nothing to wait for where the kernel has no such request
  for (size_t i = 0; i < bytes.size(); ++i) ASSERT_EQ(bytes[i], uint8_t(i * 131 + 7)) << "byte " << i;
}

TEST(Prefault, ConcurrentWritesStay) {
  std::vector<uint8_t> bytes(size_t(16) << 20);
  std::future<void> done = prefaultAsync(bytes.data(), bytes.size(), 0);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(i ^ (i >> 12));  // written while it runs
  if (done.valid()) done.wait();  // nothing to wait for where the kernel has no such request
  for (size_t i = 0; i < bytes.size(); ++i) ASSERT_EQ(bytes[i], uint8_t(i ^ (i >> 12))) << "byte " << i;
}

TEST(Prefault, SmallOrMissingRangesStartNothing) {
  std::vector<uint8_t> bytes(4096 * 4);
  EXPECT_FALSE(prefaultAsync(bytes.data(), bytes.size()).valid());  // below the default 64 MiB
  EXPECT_FALSE(prefaultAsync(nullptr, size_t(1) << 30, 0).valid());
  EXPECT_FALSE(prefaultAsync(bytes.data() + 1, 100, 0).valid());  // no whole page inside
}

}  // namespace
}  // namespace pvrt
