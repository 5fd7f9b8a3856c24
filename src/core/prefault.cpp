#include "core/prefault.h"

#include <cstdint>

#include "parallel/parallel_for.h"

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pvrt {

namespace {

// The whole pages of [data, data + bytes): those partly outside the range belong to the same
// allocation or are mapped already, and madvise() takes page-aligned addresses.
struct Pages {
  uintptr_t begin = 0, end = 0;
};
Pages wholePages(const void* data, size_t bytes) {
#if defined(__linux__)
  const auto page = uintptr_t(sysconf(_SC_PAGESIZE));
  return {(uintptr_t(data) + page - 1) & ~(page - 1), (uintptr_t(data) + bytes) & ~(page - 1)};
#else
  (void)data;
  (void)bytes;
  return {};
#endif
}

void populate(Pages p) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  // A failure (an older kernel, no memory to spare yet) only leaves the faults to the writer.
  (void)madvise(reinterpret_cast<void*>(p.begin), p.end - p.begin, MADV_POPULATE_WRITE);
#else
  (void)p;
#endif
}

}  // namespace

std::future<void> prefaultAsync(const void* data, size_t bytes, size_t minBytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  if (data == nullptr || bytes < minBytes) return {};
  const Pages p = wholePages(data, bytes);
  if (p.end <= p.begin) return {};
  return std::async(std::launch::async, [p] { populate(p); });
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
  const Pages p = wholePages(data, bytes);
  if (p.end <= p.begin) return;
  const auto page = uintptr_t(sysconf(_SC_PAGESIZE));
  const size_t pages = (p.end - p.begin) / page;
  parallelBlocks(Blocks(pages, threads, (size_t(2) << 20) / page), threads, [&](size_t, size_t lo, size_t hi) {
    populate({p.begin + lo * page, p.begin + hi * page});
  });
#else
  (void)data;
  (void)bytes;
  (void)threads;
  (void)minBytes;
#endif
}

}  // namespace pvrt
