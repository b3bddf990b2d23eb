#include "tools/stop_signals.h"

#include "tools/run/stop_request.h"

#include <signal.h>
#include <unistd.h>

#include <initializer_list>

namespace csim::cli {

namespace {

// Only async-signal-safe calls here: the flag, signal(), raise(), write().
void on_stop_signal(int signal) {
  if (stop_request() != 0) {  // the second: the default action, at once
    ::signal(signal, SIG_DFL);
    ::raise(signal);
    return;
  }
  request_stop(signal);
  static const char note[] = "\ncsim: stopping at the next step (signal again to stop at once)\n";
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, note, sizeof note - 1);
}

}  // namespace

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction previous {};
    // A signal ignored by whoever started csim (nohup, a background job) stays ignored.
    if (::sigaction(signal, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) continue;
    ::sigaction(signal, &action, nullptr);
  }
}

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

}  // namespace csim::cli
