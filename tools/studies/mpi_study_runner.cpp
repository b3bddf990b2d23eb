// The MPI study runner. Protocol (tags kRequest and kAssign on MPI_COMM_WORLD): a worker sends rank 0 a
// request [index of the case it finished or −1][kind][record], rank 0 answers with the index of the next
// case, or −1 when there is none left (or the study is stopping), and the worker leaves. Rank 0 serves
// these requests from a thread of its own while its main thread runs cases from the same counter; that
// thread polls with short sleeps rather than blocking in MPI, whose blocking calls spin and would take
// the core that rank 0's own cases run on. Waits of the workers outside a case (the folder shared, the
// end of the study) poll the same way.
#include "tools/studies/mpi_study_runner.h"

#include "tools/run/stop_request.h"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#ifdef CSIM_HAVE_MPI
#include <mpi.h>
#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>
#include <vector>
#endif

namespace csim {

bool started_by_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

#ifndef CSIM_HAVE_MPI

bool mpi_built_in() { return false; }

namespace {

// The size of the job as the launcher's environment gives it; 0 when not known (PMIx gives only the rank).
int launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 0;
}

}  // namespace

std::unique_ptr<StudyRunner> make_mpi_runner(int&, char**&) {
  if (started_by_mpi_launcher() && launcher_size() != 1)
    throw std::runtime_error("started by an MPI launcher, but this csim was built without MPI: each rank would "
                             "run the whole study; rebuild with MPI (libopenmpi-dev) or run csim without mpirun");
  return nullptr;
}

#else

bool mpi_built_in() { return true; }

namespace {

constexpr int kRequest = 1, kAssign = 2;
enum Kind : char { kFirst = 0, kResult = 1, kStopped = 2, kFailed = 3 };
constexpr auto kPoll = std::chrono::milliseconds(1);

// Waits for a non-blocking operation without spinning.
void wait_quietly(MPI_Request& request) {
  int done = 0;
  while (MPI_Test(&request, &done, MPI_STATUS_IGNORE), !done) std::this_thread::sleep_for(kPoll);
}

// The CPUs this process may run on: "cpu 3", "cpus 0-3", "cpus 0,2".
std::string affinity_text() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return "cpus unknown";
  std::string list;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (!CPU_ISSET(c, &set)) continue;
    int last = c;
    while (last + 1 < CPU_SETSIZE && CPU_ISSET(last + 1, &set)) ++last;
    list += (list.empty() ? "" : ",") + std::to_string(c) + (last > c ? "-" + std::to_string(last) : "");
    c = last;
  }
  return (CPU_COUNT(&set) == 1 ? "cpu " : "cpus ") + list;
}

std::string host_name() {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  return name;
}

std::string request_bytes(std::int64_t finished, Kind kind, const std::string& record) {
  std::string bytes(sizeof finished + 1, '\0');
  std::memcpy(bytes.data(), &finished, sizeof finished);
  bytes[sizeof finished] = kind;
  return bytes + record;
}

class MpiStudyRunner : public StudyRunner {
 public:
  MpiStudyRunner(int& argc, char**& argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    // A library that cannot hand MPI from one thread to another: rank 0 only serves the others.
    root_runs_cases_ = provided >= MPI_THREAD_SERIALIZED;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    gather_placement();
  }
  ~MpiStudyRunner() override { MPI_Finalize(); }

  // Signalled, OpenMPI's mpirun (4.1) sends every rank SIGTERM, whatever its own signal, then SIGKILL, each
  // after odls_base_sigkill_timeout (1 s), and exits 1 whatever its ranks do; when the signal reached the
  // ranks themselves (srun, scancel, a kill of the ranks), it reports their status. Either way MPI_Finalize
  // waits on the launcher's teardown (1-2 s, or for ever if it does not answer). The ranks meet once more
  // by themselves (no launcher involved), rank 0 having removed its temporary folder by then, so
  // that a launcher that takes the job down when a rank exits does not kill rank 0 in its cleanup; the
  // wait is bounded, for a rank that will never come (killed, or not stopped), and each leaves with _Exit.
  void leave_at_once(int status) override {
    MPI_Request request;
    MPI_Ibarrier(MPI_COMM_WORLD, &request);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    int done = 0;
    while (MPI_Test(&request, &done, MPI_STATUS_IGNORE), !done && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(kPoll);
    std::fflush(nullptr);
    std::_Exit(status);
  }

  bool is_root() const override { return rank_ == 0; }
  Placement placement() const override { return placement_; }

  std::string share(const std::string& text) override {
    std::int64_t size = static_cast<std::int64_t>(text.size());
    MPI_Request request;
    MPI_Ibcast(&size, 1, MPI_INT64_T, 0, MPI_COMM_WORLD, &request);
    wait_quietly(request);
    std::string shared = rank_ == 0 ? text : std::string(static_cast<std::size_t>(size), '\0');
    MPI_Ibcast(shared.data(), static_cast<int>(size), MPI_BYTE, 0, MPI_COMM_WORLD, &request);
    wait_quietly(request);
    return shared;
  }

  void run(std::size_t count, const std::function<std::string(std::size_t)>& run_case,
           const std::function<void(std::size_t, const std::string&)>& on_record) override {
    // The outcome of the study, from rank 0 to all: 0 done, a signal number (stopped), −1 failed.
    std::int64_t outcome = rank_ == 0 ? serve_and_run(count, run_case, on_record) : work(run_case);
    MPI_Request request;
    MPI_Ibcast(&outcome, 1, MPI_INT64_T, 0, MPI_COMM_WORLD, &request);
    wait_quietly(request);
    if (outcome > 0) throw StopRequested{static_cast<int>(outcome)};
    if (outcome < 0) throw std::runtime_error(failure_.empty() ? "the study failed on another rank" : failure_);
  }

 private:
  void gather_placement() {
    constexpr int kWidth = 128;
    char mine[kWidth] = {};
    const std::string text = host_name() + '\n' + affinity_text();
    std::strncpy(mine, text.c_str(), kWidth - 1);
    std::vector<char> all(rank_ == 0 ? static_cast<std::size_t>(kWidth) * size_ : 0);
    MPI_Gather(mine, kWidth, MPI_CHAR, all.data(), kWidth, MPI_CHAR, 0, MPI_COMM_WORLD);
    placement_.mpi = true;
    placement_.ranks = size_;
    if (rank_ != 0) return;
    std::vector<std::pair<std::string, std::string>> ranks;  // host, cpus
    bool one_host = true;
    for (int r = 0; r < size_; ++r) {
      const std::string entry(&all[static_cast<std::size_t>(r) * kWidth]);
      const std::size_t newline = entry.find('\n');
      ranks.emplace_back(entry.substr(0, newline), entry.substr(newline + 1));
      one_host = one_host && ranks.back().first == ranks.front().first;
    }
    std::string binding;
    for (int r = 0; r < size_; ++r)
      binding += (r ? "; " : "") + std::string("rank ") + std::to_string(r) + (one_host ? "" : " on " + ranks[r].first) +
                 " " + ranks[r].second;
    placement_.binding = binding + (root_runs_cases_ ? "" : " (rank 0 runs no case: MPI gives no thread support)");
  }

  // A worker: asks for cases until there are none left. Returns what rank 0 broadcasts in run().
  std::int64_t work(const std::function<std::string(std::size_t)>& run_case) {
    std::int64_t finished = -1;
    Kind kind = kFirst;
    std::string record;
    while (true) {
      const std::string request = request_bytes(finished, kind, record);
      MPI_Send(request.data(), static_cast<int>(request.size()), MPI_BYTE, 0, kRequest, MPI_COMM_WORLD);
      std::int64_t next = -1;
      MPI_Request receive;
      MPI_Irecv(&next, 1, MPI_INT64_T, 0, kAssign, MPI_COMM_WORLD, &receive);
      wait_quietly(receive);
      if (next < 0) break;
      try {
        honour_stop_request();
        record = run_case(static_cast<std::size_t>(next));
        kind = kResult;
        finished = next;
      } catch (const StopRequested& stop) {
        kind = kStopped;
        record = std::to_string(stop.signal);
      } catch (const std::exception& e) {
        kind = kFailed;
        record = e.what();
      }
    }
    return 0;
  }

  struct Shared {
    std::mutex mutex;
    std::condition_variable changed;
    std::size_t next = 0, count = 0;
    std::map<std::size_t, std::string> records;  // finished, not yet reported
    bool stopping = false, served = false;
    int signal = 0;
    std::string failure;
    // The index of the next case, or −1 when none is left or the study is stopping.
    std::int64_t take() {
      std::lock_guard<std::mutex> lock(mutex);
      if (stopping || next >= count) return -1;
      return static_cast<std::int64_t>(next++);
    }
  };

  // Rank 0's thread of messages: answers every worker until each has been told that no case is left.
  void serve(Shared& shared) {
    int active = size_ - 1;
    while (active > 0) {
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, kRequest, MPI_COMM_WORLD, &arrived, &status);
      if (!arrived) {
        std::this_thread::sleep_for(kPoll);
        continue;
      }
      int size = 0;
      MPI_Get_count(&status, MPI_BYTE, &size);
      std::string bytes(static_cast<std::size_t>(size), '\0');
      MPI_Recv(bytes.data(), size, MPI_BYTE, status.MPI_SOURCE, kRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      std::int64_t finished = -1;
      std::memcpy(&finished, bytes.data(), sizeof finished);
      const Kind kind = static_cast<Kind>(bytes[sizeof finished]);
      std::string record = bytes.substr(sizeof finished + 1);
      {
        std::lock_guard<std::mutex> lock(shared.mutex);
        if (kind == kResult) shared.records[static_cast<std::size_t>(finished)] = std::move(record);
        if (kind == kStopped && !shared.stopping) shared.signal = std::atoi(record.c_str());
        if (kind == kFailed && shared.failure.empty()) shared.failure = "rank " + std::to_string(status.MPI_SOURCE) + ": " + record;
        if (kind == kStopped || kind == kFailed) shared.stopping = true;
      }
      shared.changed.notify_all();
      const std::int64_t next = shared.take();
      if (next < 0) --active;
      MPI_Send(&next, 1, MPI_INT64_T, status.MPI_SOURCE, kAssign, MPI_COMM_WORLD);
    }
    std::lock_guard<std::mutex> lock(shared.mutex);
    shared.served = true;
    shared.changed.notify_all();
  }

  std::int64_t serve_and_run(std::size_t count, const std::function<std::string(std::size_t)>& run_case,
                             const std::function<void(std::size_t, const std::string&)>& on_record) {
    Shared shared;
    shared.count = count;
    std::size_t reported = 0;
    // Reports, in case order, what has finished; on_record runs on this thread only.
    auto report = [&] {
      while (true) {
        std::string record;
        {
          std::lock_guard<std::mutex> lock(shared.mutex);
          const auto found = shared.records.find(reported);
          if (found == shared.records.end()) return;
          record = std::move(found->second);
          shared.records.erase(found);
        }
        on_record(reported++, record);
      }
    };
    if (!root_runs_cases_) {
      serve(shared);
      report();
    } else {
      std::thread server([&] { serve(shared); });
      try {
        for (std::int64_t index; (index = shared.take()) >= 0;) {
          honour_stop_request();
          std::string record = run_case(static_cast<std::size_t>(index));
          {
            std::lock_guard<std::mutex> lock(shared.mutex);
            shared.records[static_cast<std::size_t>(index)] = std::move(record);
          }
          report();
        }
      } catch (const StopRequested& stop) {
        std::lock_guard<std::mutex> lock(shared.mutex);
        shared.stopping = true;
        shared.signal = stop.signal;
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(shared.mutex);
        shared.stopping = true;
        if (shared.failure.empty()) shared.failure = e.what();
      }
      while (true) {  // the workers' last cases, reported as they come
        bool served = false;
        {
          std::unique_lock<std::mutex> lock(shared.mutex);
          shared.changed.wait(lock, [&] { return shared.served || shared.records.count(reported) > 0; });
          served = shared.served;
        }
        report();
        if (served) break;
      }
      server.join();
      report();
    }
    failure_ = shared.failure;
    if (!shared.failure.empty()) return -1;
    if (shared.stopping) return shared.signal > 0 ? shared.signal : 15;
    return 0;
  }

  int rank_ = 0, size_ = 1;
  bool root_runs_cases_ = true;
  Placement placement_;
  std::string failure_;
};

}  // namespace

std::unique_ptr<StudyRunner> make_mpi_runner(int& argc, char**& argv) {
  if (!started_by_mpi_launcher()) return nullptr;
  return std::make_unique<MpiStudyRunner>(argc, argv);
}

#endif

}  // namespace csim
