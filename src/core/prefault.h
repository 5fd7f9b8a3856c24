// Faulting memory in ahead of its first use, on another thread.
#pragma once

#include <cstddef>
#include <future>
#include <vector>

namespace pvrt {

// Starts faulting in the pages of [data, data + bytes) on another thread (Linux's
// MADV_POPULATE_WRITE, which maps pages without changing what they hold), so that a thread
// about to fill that memory front to back finds its pages there. On the 2-core VMs we
// measure on, memory that a process touches for the first time costs about 1.3 s a GiB
// (the kernel clears every page), work the other core can do meanwhile. Nothing happens
// below `minBytes`, off Linux, or where the kernel does not know the request. The memory
// must outlive the returned future's wait (its destructor waits).
std::future<void> prefaultAsync(const void* data, size_t bytes, size_t minBytes = size_t(64) << 20);

// Faults in the pages of [data, data + bytes) now, a block of pages on each of up to `threads`
// threads (0: threadBudget()), so that one thread about to fill that memory does not clear
// every page itself. Nothing happens below `minBytes`, off Linux, or where the kernel does not
// know the request.
void prefault(const void* data, size_t bytes, int threads, size_t minBytes = size_t(4) << 20);

// v.resize(n), the new elements' pages faulted in first by up to `threads` threads: for big
// vectors that one thread then constructs, or that threads fill after their construction.
template <class T>
void resizePrefaulted(std::vector<T>& v, size_t n, int threads) {
  if (n > v.size()) {
    v.reserve(n);
    prefault(v.data() + v.size(), (n - v.size()) * sizeof(T), threads);
  }
  v.resize(n);
}

}  // namespace pvrt
