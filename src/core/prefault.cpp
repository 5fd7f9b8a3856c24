#include "core/prefault.h"

#include <cstdint>

#include "parallel/parallel_for.h"

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pvrt {

std::future<void> prefaultAsync(const void* data, size_t bytes, size_t minBytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  if (data == nullptr || bytes < minBytes) return {};
  const auto page = uintptr_t(sysconf(_SC_PAGESIZE));
  // Whole pages only: those partly outside the range belong to the same allocation or are
  // mapped already, and madvise() takes page-aligned addresses.
  const uintptr_t begin = (uintptr_t(data) + page - 1) & ~(page - 1);
  const uintptr_t end = (uintptr_t(data) + bytes) & ~(page - 1);
  if (end <= begin) return {};
  return std::async(std::launch::async, [begin, end] {
    // A failure (an older kernel, no memory to spare yet) only leaves the faults to the writer.
    (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
  });
#else
  (void)data;
  (void)bytes;
  (void)minBytes;
  return {};
#endif
}

void prefault(const void* data, size_t bytes, int threads, size_t minBytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  if (data == nullptr || bytes < minBytes) return;
  const auto page = uintptr_t(sysconf(_SC_PAGESIZE));
  const uintptr_t begin = (uintptr_t(data) + page - 1) & ~(page - 1);
  const uintptr_t end = (uintptr_t(data) + bytes) & ~(page - 1);
  if (end <= begin) return;
  const size_t pages = (end - begin) / page;
  parallelBlocks(Blocks(pages, threads, (size_t(2) << 20) / page), threads, [&](size_t, size_t lo, size_t hi) {
    (void)madvise(reinterpret_cast<void*>(begin + lo * page), (hi - lo) * page, MADV_POPULATE_WRITE);
  });
#else
  (void)data;
  (void)bytes;
  (void)threads;
  (void)minBytes;
#endif
}

}  // namespace pvrt
