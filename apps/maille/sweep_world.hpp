// The processes of a sweep: MPI when this maille has it (built with Open MPI) and a launcher
// (mpirun, srun) started the process; otherwise a world of one process that runs every case.
//
// Cases are handed out one at a time by rank 0 (docs/sweep.md, "How cases are handed out"):
//
//   rank 0   main thread:       take a case, run it, record it, take the next ...
//            dispatcher thread: Iprobe / sleep 1 ms; on a request from rank r: record the case
//                               r finished, answer with the next case (or "no more")
//   rank r   take a case from rank 0, run it, send its result with the next request ...
//
// Only the dispatcher thread calls MPI while cases run (MPI_THREAD_SERIALIZED), and it sleeps
// between probes: it costs rank 0 no core, and a rank waits at most about a millisecond for
// its next case, so a slow case delays no other.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "sweep_case.hpp"

namespace maille::app {

// What rank 0's dispatcher does with the other ranks' requests (thread-safe callbacks).
struct Dispatch {
  std::function<std::optional<std::uint64_t>()> take;  // the next case, or none (no more / stop)
  std::function<void(std::uint64_t)> give_back;        // handed out, but its rank stopped first
  std::function<void(CaseResult)> record;              // a case another rank finished
  std::function<void()> idle;                          // between probes (the summary's cadence)
};

class World {
 public:
  // Starts MPI if this maille has it and was launched by mpirun or srun. Returns null, with a
  // message on stderr, when it cannot start (or when launched as several ranks without MPI).
  static std::unique_ptr<World> start();
  ~World();  // MPI_Finalize
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Rank 0 can run cases beside its dispatcher thread (the MPI library allows calls from it).
  bool dispatcher_thread() const { return serialized_; }
  // Rank 0's `value`, on every rank (a collective: every rank calls it).
  int broadcast(int value) const;
  // Rank 0: answers the other ranks until each has been told there is no more work or has
  // stopped. Run in a thread of its own when dispatcher_thread(), else in the main thread.
  void serve(const Dispatch& d) const;
  // Ranks > 0: cases from rank 0, run by `run`, until none is left or `stop` >= 1.
  void work(const std::function<CaseResult(std::uint64_t)>& run,
            const std::atomic<int>& stop) const;

 private:
  World() = default;
  int rank_ = 0, size_ = 1;
  bool mpi_ = false;
  bool serialized_ = true;
};

}  // namespace maille::app
