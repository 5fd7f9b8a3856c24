// SIGINT and SIGTERM, caught once for the whole process. Every long loop (reading a scene,
// loading it, building the BVH and the light buffers, rendering, down to each ray of a deep
// trace) asks requested() often enough that a signal ends pvrt within a fraction of a
// second; pvrt then exits with 128 + the signal (130 for SIGINT, 143 for SIGTERM), having
// written nothing. A second signal ends the process at once.
//
// Inside a parallel loop a body cannot throw (parallelIndices), so bodies return early when
// requested() and the caller calls check() after the loop.
#pragma once

#include <atomic>

#include "core/error.h"

namespace pvrt::interrupt {

// Installs the handlers (idempotent). Without them requested() stays false unless set().
// `lastWish`, when given, runs in the handler of a second signal just before the process
// ends (so it must be async-signal-safe): what is left on disk is removed.
void install(void (*lastWish)() = nullptr);

// The signal caught so far (SIGINT or SIGTERM), or 0.
inline std::atomic<int>& caught() {
  static std::atomic<int> signal{0};
  return signal;
}
inline bool requested() { return caught().load(std::memory_order_relaxed) != 0; }
// Acts as if `signal` had been caught (tests, and the MPI backend forwarding a rank's).
void set(int signal);
void clear();

// 128 + the signal caught (130 when none was).
ExitCode exitCode();
// The error that ends an interrupted run: exit code 128 + signal, the one line
// `pvrt: interrupted; nothing was written`.
Error error();
// Throws error() when a signal was caught.
inline void check() {
  if (requested()) throw error();
}

}  // namespace pvrt::interrupt
