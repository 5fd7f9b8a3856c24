#include "core/interrupt.h"

#include <signal.h>
#include <unistd.h>

namespace pvrt::interrupt {

namespace {
std::atomic<void (*)()> gLastWish{nullptr};

extern "C" void onSignal(int signal) {
  int none = 0;
  // The first signal asks every loop to stop; a second one ends the process at once, after
  // the last wish (removing the temporaries of outputs not yet committed).
  if (!caught().compare_exchange_strong(none, signal)) {
    if (void (*wish)() = gLastWish.load()) wish();
    _exit(128 + caught().load());
  }
}
}  // namespace

void install(void (*lastWish)()) {
  gLastWish.store(lastWish);
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a read waiting on a pipe returns EINTR
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void set(int signal) { caught().store(signal); }
void clear() { caught().store(0); }

ExitCode exitCode() {
  const int s = caught().load();
  return ExitCode(128 + (s > 0 ? s : SIGINT));
}

Error error() { return Error(exitCode(), "pvrt: interrupted; nothing was written"); }

}  // namespace pvrt::interrupt
