// A regular file mapped read-only into memory, for the loader of big scenes: its pages come
// straight from the page cache, where reading them would first have the kernel clear as much
// fresh memory and then copy the file into it (243 MB: 0.26-0.66 s on the 2-core VM, against
// 0.04 s to map and touch every page).
//
// A mapped file that shrinks while it is read would kill the process with SIGBUS at the first
// page past its new end. While a MappedFile lives, a SIGBUS at one of its pages instead maps a
// page of zeros there and marks the file `shrunk()`: the reader gets zeros (which no scene
// holds), and the loader then reads the file again the ordinary way. Any other SIGBUS gets
// the action that was in place before.
#pragma once

#include <atomic>
#include <cstddef>
#include <string>
#include <string_view>

namespace pvrt {

class MappedFile {
 public:
  // Maps the regular file open as `fd` (which may be closed afterwards), of `size` bytes;
  // !ok() when it cannot be mapped (the caller reads it instead).
  MappedFile(int fd, size_t size);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  bool ok() const { return data_ != nullptr; }
  std::string_view bytes() const { return {data_, size_}; }
  // Unmaps the whole pages within [begin, end): a later read of them reads the file again.
  // Several threads may drop disjoint ranges at once. True when some page was dropped.
  bool drop(size_t begin, size_t end) const;
  // Whether a page past the file's end was read (the file shrank after it was mapped).
  bool shrunk() const { return shrunk_.load(std::memory_order_acquire); }

 private:
  char* data_ = nullptr;
  size_t size_ = 0;  // the bytes mapped
  size_t mapped_ = 0;  // rounded up to whole pages
  int slot_ = -1;    // in the SIGBUS guard's table
  std::atomic<bool> shrunk_{false};
};

}  // namespace pvrt
