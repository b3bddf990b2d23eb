#include "tools/studies/case_failure.h"

#include "engine/steppers/stepper.h"

#include <exception>
#include <limits>
#include <new>
#include <sstream>
#include <system_error>

namespace csim {

CaseFailure current_case_failure() {
  CaseFailure failure;
  failure.time = std::numeric_limits<double>::quiet_NaN();
  try {
    throw;
  } catch (const RunError& e) {
    failure.kind = CaseFailureKind::numerical_failure;
    failure.time = e.time;
    std::ostringstream message;
    message << "numerical failure at t = " << e.time << " s: " << e.what();
    failure.message = message.str();
  } catch (const std::bad_alloc&) {
    failure.kind = CaseFailureKind::environment_failure;
    failure.message = "out of memory (the system refused an allocation)";
  } catch (const std::system_error& e) {
    failure.kind = CaseFailureKind::environment_failure;
    failure.message = e.what();
  } catch (const std::exception& e) {
    failure.kind = CaseFailureKind::bad_input;
    failure.message = e.what();
  }
  return failure;
}

const char* case_failure_status(CaseFailureKind kind) {
  switch (kind) {
    case CaseFailureKind::bad_input: return "bad input";
    case CaseFailureKind::numerical_failure: return "numerical failure";
    case CaseFailureKind::environment_failure: return "environment failure";
  }
  return "?";
}

}  // namespace csim
