// Faulting memory in ahead of its first use, on another thread.
#pragma once

#include <cstddef>
#include <future>

namespace pvrt {

// Starts faulting in the pages of [data, data + bytes) on another thread (Linux's
// MADV_POPULATE_WRITE, which maps pages without changing what they hold), so that a thread
// about to fill that memory front to back finds its pages there. On the 2-core VMs we
// measure on, memory that a process touches for the first time costs about 1.3 s a GiB
// (the kernel clears every page), work the other core can do meanwhile. Nothing happens
// below `minBytes`, off Linux, or where the kernel does not know the request. The memory
// must outlive the returned future's wait (its destructor waits).
std::future<void> prefaultAsync(const void* data, size_t bytes, size_t minBytes = size_t(64) << 20);

// The same on the calling thread, whatever the size: for a memory that several threads
// fault in a part each.
void prefault(const void* data, size_t bytes);

}  // namespace pvrt
