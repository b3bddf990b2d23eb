// The study runner: the one way `csim compare`, `csim stress` and `csim sweep` run their cases. A study
// is a list of independent cases, numbered 0 … n−1; the runner runs each once and hands its record
// (case_record.h) to rank 0 in case order, whatever order the cases finished in, so that a study's
// outputs do not depend on how it was placed.
//
// Serially (the default) the cases run one after the other in this process. Started by mpirun or srun
// (mpi_study_runner.h), the cases are handed out dynamically: rank 0 keeps the index of the next case,
// each rank asks for a new one when it has finished the last, so that long cases leave no rank idle;
// rank 0 runs cases too, its messages served by a thread of its own. Only rank 0 reports results and
// writes the study's outputs (is_root()).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

namespace csim {

// How a study was placed, for the header of its CSV: "serial (1 process)" or "MPI: 2 ranks, binding
// rank 0 cpu 0, rank 1 cpu 1". Binding is what each rank's CPU affinity was, as the OS reports it.
struct Placement {
  int ranks = 1;
  bool mpi = false;
  std::string binding;  // per rank, the CPUs it may run on ("rank 0 cpu 0, rank 1 cpu 1"); empty serially
  std::string text() const;
};

class StudyRunner {
 public:
  virtual ~StudyRunner() = default;

  // Whether this process reports results and writes outputs (rank 0, or the only process).
  virtual bool is_root() const { return true; }
  virtual Placement placement() const { return {}; }

  // Rank 0's value of `text` on every rank (the temporary output folder, where cases write their own
  // outputs). Serially, `text` itself.
  virtual std::string share(const std::string& text) { return text; }

  // Runs cases 0 … count−1, each once, by run_case on whichever rank is free, and calls on_record on the
  // root with each record in case order (never in completion order). run_case must turn every failure of
  // its case into its record; a StopRequested it throws (stop_request.h) stops the study: no new case
  // starts, and run throws StopRequested on every rank once the cases under way are done.
  virtual void run(std::size_t count, const std::function<std::string(std::size_t)>& run_case,
                   const std::function<void(std::size_t, const std::string&)>& on_record);

  // Ends this process at once with `status`, skipping the runner's orderly shutdown, for a command that a
  // stop request ended (stop_request.h) once it has cleaned up: under MPI, MPI_Finalize would wait for a
  // launcher that is taking the job down. Serially there is nothing to skip: returns.
  virtual void leave_at_once(int status) { (void)status; }
};

// The serial runner, for library callers and tests.
StudyRunner& serial_runner();

}  // namespace csim
