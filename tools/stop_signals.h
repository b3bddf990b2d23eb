// SIGINT, SIGTERM and SIGHUP (the terminal closed, the session ended) for the commands that write an
// output folder (run, compare, stress, sweep): the first asks the command to stop at its next step
// boundary or between runs (tools/run/stop_request.h), so that it removes its temporary folder and leaves
// the destination as it was, then exits 128 + the signal (130, 143, 129); a second one stops it at once,
// with the signal's default action. A signal that whoever started csim ignores (nohup) stays ignored.
#pragma once

namespace csim::cli {

void install_stop_handlers();

// "SIGINT", "SIGTERM", "SIGHUP".
const char* signal_name(int signal);

}  // namespace csim::cli
