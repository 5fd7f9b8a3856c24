// The memory that pvrt's optional acceleration structures may take (`--memory-limit`): the
// BVH is always built, and what it leaves of the limit goes to the light buffers; lights that
// do not fit go without one, which changes the work done, never the image. Without
// --memory-limit the light buffers also take at most a share that grows with the scene
// (render/scene.h, lightBufferBudget).
#pragma once

#include <cstddef>
#include <string>

namespace pvrt {

// The memory this process may use: the machine's physical memory, or the cgroup's limit
// (memory.max, v2; memory.limit_in_bytes, v1) where that is smaller.
size_t availableMemory();

// The default limit: a quarter of availableMemory(), so that two or three renders (or MPI
// ranks) on one machine, with their scene descriptions and images, still fit beside each other.
size_t defaultMemoryLimit();

// "2G", "512M", "1.5G", "100000K", "4096" (bytes): a positive number with an optional binary
// suffix K, M, G or T. Throws pvrt::Error(Usage) naming --memory-limit otherwise.
size_t parseMemorySize(const std::string& text);

// "1.5 GiB", "512.0 MiB", for messages.
std::string formatBytes(size_t bytes);

}  // namespace pvrt
