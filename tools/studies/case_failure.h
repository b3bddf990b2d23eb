// What ended a case of a study (or a run of csim run) before its end, read from the exception it threw,
// so that every study names it alike (docs/contract.md):
//   numerical failure    a RunError of the stepper or the contact solver, at its time;
//   environment failure  the machine's, not the scene's: out of memory (std::bad_alloc), a file or folder
//                        that cannot be written (FileWriteError: a full disk, a quota, a permission), or
//                        any other refusal of the system (std::system_error); the message gives the
//                        system's reason;
//   bad input            any other error: a value the scene or the integrator rejects.
// StopRequested is not a failure of the case (stop_request.h) and is never caught here.
#pragma once

#include <string>

namespace csim {

enum class CaseFailureKind { bad_input, numerical_failure, environment_failure };

struct CaseFailure {
  CaseFailureKind kind = CaseFailureKind::bad_input;
  std::string message;  // one line; a numerical failure's says at what time
  double time = 0.0;    // s, of a numerical failure (NaN for the others)
};

// The failure that the exception being handled stands for; call it in a catch (const std::exception&)
// block (or catch (...) when only std::exception may arrive).
CaseFailure current_case_failure();

// "bad input", "numerical failure", "environment failure": the status column of sweep.csv.
const char* case_failure_status(CaseFailureKind kind);

}  // namespace csim
