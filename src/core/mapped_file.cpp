#include "core/mapped_file.h"

#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <mutex>

namespace pvrt {

namespace {

// The mappings the SIGBUS handler answers for. The handler reads them without a lock (it
// may interrupt any code), so each field is an atomic, and a slot's range is published
// after its flag and cleared before the mapping goes.
struct Guarded {
  std::atomic<uintptr_t> begin{0}, end{0};
  std::atomic<std::atomic<bool>*> shrunk{nullptr};
};
constexpr int kSlots = 16;
Guarded slots[kSlots];

std::mutex guardMutex;  // over the slots' use and the handler's installation
int guardedCount = 0;
struct sigaction previousAction;
std::atomic<uintptr_t> pageSize{4096};

void onBusError(int sig, siginfo_t* info, void*) {
  const auto at = uintptr_t(info->si_addr);
  // A fault (not a SIGBUS sent by kill()) at one of our mappings' pages: zeros there.
  if (info->si_code > 0) {
    for (Guarded& g : slots) {
      if (at < g.begin.load(std::memory_order_acquire) || at >= g.end.load(std::memory_order_acquire)) continue;
      std::atomic<bool>* shrunk = g.shrunk.load(std::memory_order_acquire);
      const uintptr_t page = at & ~(pageSize.load(std::memory_order_relaxed) - 1);
      if (!shrunk || ::mmap(reinterpret_cast<void*>(page), pageSize.load(std::memory_order_relaxed), PROT_READ,
                            MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0) == MAP_FAILED)
        break;
      shrunk->store(true, std::memory_order_release);
      return;  // the read is done again, from the zero page
    }
  }
  // Not ours: the action that was in place before, for this signal and any later one.
  ::sigaction(SIGBUS, &previousAction, nullptr);
  if (info->si_code <= 0) ::raise(sig);  // sent, not a fault: send it again
  // A fault repeats when the instruction does, now with the previous action.
}

int guard(char* data, size_t bytes, std::atomic<bool>* shrunk) {
  const std::lock_guard<std::mutex> lock(guardMutex);
  for (int s = 0; s < kSlots; ++s) {
    Guarded& g = slots[s];
    if (g.end.load(std::memory_order_relaxed) != 0) continue;
    if (guardedCount == 0) {
      pageSize.store(uintptr_t(::sysconf(_SC_PAGESIZE)), std::memory_order_relaxed);
      struct sigaction a {};
      a.sa_sigaction = onBusError;
      a.sa_flags = SA_SIGINFO;
      sigemptyset(&a.sa_mask);
      if (::sigaction(SIGBUS, &a, &previousAction) != 0) return -1;
    }
    ++guardedCount;
    g.shrunk.store(shrunk, std::memory_order_release);
    g.begin.store(uintptr_t(data), std::memory_order_release);
    g.end.store(uintptr_t(data) + bytes, std::memory_order_release);
    return s;
  }
  return -1;  // too many files mapped at once: the caller reads this one
}

void unguard(int s) {
  const std::lock_guard<std::mutex> lock(guardMutex);
  slots[s].end.store(0, std::memory_order_release);
  slots[s].begin.store(0, std::memory_order_release);
  slots[s].shrunk.store(nullptr, std::memory_order_release);
  if (--guardedCount == 0) ::sigaction(SIGBUS, &previousAction, nullptr);
}

}  // namespace

MappedFile::MappedFile(int fd, size_t size) {
  if (size == 0) return;
  const auto page = size_t(::sysconf(_SC_PAGESIZE));
  const size_t mapped = (size + page - 1) / page * page;
  void* p = ::mmap(nullptr, mapped, PROT_READ, MAP_PRIVATE, fd, 0);
  if (p == MAP_FAILED) return;
  slot_ = guard(static_cast<char*>(p), mapped, &shrunk_);
  if (slot_ < 0) {
    ::munmap(p, mapped);
    return;
  }
  data_ = static_cast<char*>(p);
  size_ = size;
  mapped_ = mapped;
}

MappedFile::~MappedFile() {
  if (!data_) return;
  unguard(slot_);
  ::munmap(data_, mapped_);
}

bool MappedFile::drop(size_t begin, size_t end) const {
  if (!data_ || begin >= end || end > size_) return false;
  const auto page = uintptr_t(::sysconf(_SC_PAGESIZE));
  const uintptr_t from = (uintptr_t(data_ + begin) + page - 1) / page * page;
  const uintptr_t to = uintptr_t(data_ + end) / page * page;
  return from < to && ::madvise(reinterpret_cast<void*>(from), to - from, MADV_DONTNEED) == 0;
}

}  // namespace pvrt
