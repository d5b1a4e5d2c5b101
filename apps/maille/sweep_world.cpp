#include "sweep_world.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#ifdef MAILLE_WITH_MPI
#include <mpi.h>
#endif

namespace maille::app {

namespace {

// What a launcher says it started: whether one did (Open MPI's mpirun, PMIx or PMI as used by
// srun and MPICH's hydra), and how many processes when it says (0: unknown).
struct Launch {
  bool launched = false;
  int processes = 0;
};

Launch launch() {
  Launch l;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    l.launched = l.launched || std::getenv(name) != nullptr;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(name); v && l.processes == 0) l.processes = std::atoi(v);
  return l;
}

#ifdef MAILLE_WITH_MPI
constexpr int kRequest = 1;  // rank r -> 0: "R" ask; "D"/"F" + a result (then ask / stop);
                             // "Q" + a case number (handed back, stopping); "X" stopping
constexpr int kAssign = 2;   // rank 0 -> r: a case number, or -1 for no more
constexpr auto kPoll = std::chrono::milliseconds(1);

// Waits for a request by testing it every millisecond: Open MPI's blocking calls spin a core,
// which an idle rank would take from a busy one sharing its node.
void lazy_wait(MPI_Request& request) {
  int done = 0;
  for (;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(kPoll);
  }
}

// A request to rank 0: its kind, then its text.
void send_message(char kind, const std::string& body) {
  std::vector<char> bytes(body.size() + 1);
  bytes[0] = kind;
  std::copy(body.begin(), body.end(), bytes.begin() + 1);
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_CHAR, 0, kRequest, MPI_COMM_WORLD);
}
#endif

}  // namespace

std::unique_ptr<World> World::start() {
  std::unique_ptr<World> w(new World());
  const Launch l = launch();
#ifdef MAILLE_WITH_MPI
  if (!l.launched) return w;  // run by hand: one process, and no MPI runtime to start
  int provided = MPI_THREAD_SINGLE;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) {
    std::cerr << "error: MPI could not start\n";
    return nullptr;
  }
  w->mpi_ = true;
  w->serialized_ = provided >= MPI_THREAD_SERIALIZED;
  MPI_Comm_rank(MPI_COMM_WORLD, &w->rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &w->size_);
  if (l.processes > 0 && w->size_ != l.processes && w->rank_ == 0)
    std::cerr << "warning: the launcher started " << l.processes << " processes but MPI sees "
              << w->size_ << " (srun: try --mpi=pmix)\n";
#else
  if (l.processes > 1) {
    std::cerr << "error: this maille was built without MPI but was started as one of "
              << l.processes
              << " processes (mpirun, srun): each would run every case. Build it with Open MPI "
                 "(libopenmpi-dev), or run `maille sweep` without a launcher\n";
    return nullptr;
  }
#endif
  return w;
}

World::~World() {
#ifdef MAILLE_WITH_MPI
  if (mpi_) MPI_Finalize();
#endif
}

int World::broadcast(int value) const {
#ifdef MAILLE_WITH_MPI
  if (mpi_ && size_ > 1) {
    MPI_Request request;
    MPI_Ibcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
    lazy_wait(request);
  }
#endif
  return value;
}

void World::serve(const Dispatch& d) const {
#ifdef MAILLE_WITH_MPI
  int active = size_ - 1;
  while (active > 0) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kRequest, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      d.idle();
      std::this_thread::sleep_for(kPoll);
      continue;
    }
    int bytes = 0;
    MPI_Get_count(&status, MPI_CHAR, &bytes);
    std::string message(static_cast<std::size_t>(bytes), '\0');
    MPI_Recv(message.data(), bytes, MPI_CHAR, status.MPI_SOURCE, kRequest, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    const char kind = message.empty() ? 'X' : message[0];
    if (kind == 'D' || kind == 'F') {
      auto r = CaseResult::parse(message.substr(1));
      if (r)
        d.record(std::move(*r));
      else
        std::cerr << "warning: rank " << status.MPI_SOURCE << " sent an unreadable result\n";
    } else if (kind == 'Q') {
      d.give_back(std::stoull(message.substr(1)));
    }
    if (kind == 'R' || kind == 'D') {
      const auto next = d.take();
      std::int64_t assigned = next ? static_cast<std::int64_t>(*next) : -1;
      MPI_Send(&assigned, 1, MPI_INT64_T, status.MPI_SOURCE, kAssign, MPI_COMM_WORLD);
      if (assigned < 0) --active;
    } else {
      --active;  // F, Q, X: that rank has stopped
    }
  }
#else
  (void)d;
#endif
}

void World::work(const std::function<CaseResult(std::uint64_t)>& run,
                 const std::atomic<int>& stop) const {
#ifdef MAILLE_WITH_MPI
  char kind = 'R';
  std::string body;  // the result of the case just run (D, F), or the case handed back (Q)
  for (;;) {
    if (stop.load() >= 1) {  // Ctrl-C: report what was done, take nothing more
      send_message(kind == 'D' ? 'F' : 'X', body);
      return;
    }
    send_message(kind, body);
    std::int64_t assigned = -1;
    MPI_Request request;
    MPI_Irecv(&assigned, 1, MPI_INT64_T, 0, kAssign, MPI_COMM_WORLD, &request);
    lazy_wait(request);
    if (assigned < 0) return;
    if (stop.load() >= 1) {
      send_message('Q', std::to_string(assigned));
      return;
    }
    kind = 'D';
    body = run(static_cast<std::uint64_t>(assigned)).serialize();
  }
#else
  (void)run;
  (void)stop;
#endif
}

}  // namespace maille::app
