#include "tools/studies/study_runner.h"

#include "tools/run/stop_request.h"

namespace csim {

std::string Placement::text() const {
  if (!mpi) return "serial (1 process)";
  return "MPI, " + std::to_string(ranks) + (ranks == 1 ? " rank" : " ranks") + " (rank 0 hands out the cases and runs " +
         "some), binding " + (binding.empty() ? "unknown" : binding);
}

void StudyRunner::run(std::size_t count, const std::function<std::string(std::size_t)>& run_case,
                      const std::function<void(std::size_t, const std::string&)>& on_record) {
  for (std::size_t index = 0; index < count; ++index) {
    honour_stop_request();
    const std::string record = run_case(index);
    on_record(index, record);
  }
}

StudyRunner& serial_runner() {
  static StudyRunner runner;
  return runner;
}

}  // namespace csim
