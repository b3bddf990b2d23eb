#include "tools/run/stop_request.h"

#include <csignal>

namespace csim {

namespace {

// The one type the C and C++ standards let a signal handler write to.
volatile std::sig_atomic_t pending_signal = 0;

}  // namespace

void request_stop(int signal) noexcept { pending_signal = signal; }

int stop_request() noexcept { return pending_signal; }

void honour_stop_request() {
  if (const int signal = pending_signal) throw StopRequested{signal};
}

void clear_stop_request() noexcept { pending_signal = 0; }

}  // namespace csim
