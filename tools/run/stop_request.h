// A request to stop a run or a study before its end, made from a signal handler (csim: SIGINT,
// SIGTERM) and honoured at the next step boundary of run_scene or between the runs of a study: never in
// the middle of a step or of a file being written, so that the caller can clean up and leave the
// outputs of an earlier run as they were.
#pragma once

namespace csim {

// Thrown where a request is honoured. Not a std::exception on purpose: the studies turn any
// std::exception of one run into a failed row and go on, and a stop must end the whole study.
struct StopRequested {
  int signal = 0;  // the signal that asked for it (SIGINT, SIGTERM, ...)
};

// Records the request. Async-signal-safe: it only stores the signal number.
void request_stop(int signal) noexcept;

// The signal of the pending request; 0 when there is none.
int stop_request() noexcept;

// Throws StopRequested when a stop has been requested.
void honour_stop_request();

// Forgets the request (tests, and a program that goes on after one).
void clear_stop_request() noexcept;

}  // namespace csim
