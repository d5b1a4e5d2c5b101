// A small OpenMP runtime for the threaded WebAssembly build (docs/web.md, "Threads").
//
// Clang compiles `#pragma omp` into calls to the LLVM OpenMP runtime (libomp's __kmpc_*
// entry points); Emscripten has no libomp, so the engine's OpenMP code could not link. This file
// implements the entry points the engine's constructs produce (parallel regions with
// num_threads and if, static and dynamic loops, barrier, master, single, critical, reductions)
// on Emscripten's pthreads, which are Web Workers sharing the module's memory. So the engine's
// threaded code runs in the browser as written; its results do not depend on the thread count
// (docs/architecture.md), and the browser test holds every example to its golden hash on two
// threads too.
//
// One team at a time: the thread that forks becomes thread 0 and up to kMaxThreads - 1 pooled
// workers join it; a parallel region inside another (or from a second thread while one runs)
// runs serialised on its thread, which OpenMP allows. Waits spin briefly, then sleep on a futex
// (the main browser thread's futex wait spins, which Emscripten allows there).
#include <emscripten/emscripten.h>
#include <emscripten/threading.h>
#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <utility>

#include "omp.h"

namespace {

constexpr int kMaxThreads = 4;  // the largest team (the pool holds kMaxThreads - 1 workers)
constexpr int kMaxArgs = 32;    // captured variables of one parallel region
constexpr int kSlots = 8;       // dynamic loops a thread may be ahead of the slowest by

using Micro = void (*)(std::int32_t*, std::int32_t*, ...);

void fail(const char* what) {
  std::fprintf(stderr, "maille web OpenMP runtime: %s\n", what);
  std::abort();
}

// Waits while `word` holds `value`: a short spin, then the futex.
void wait_while(const std::atomic<std::uint32_t>& word, std::uint32_t value) {
  for (int i = 0; i < 4000; ++i)
    if (word.load(std::memory_order_acquire) != value) return;
  while (word.load(std::memory_order_acquire) == value)
    emscripten_futex_wait(const_cast<std::atomic<std::uint32_t>*>(&word), value, INFINITY);
}

void wake_all(std::atomic<std::uint32_t>& word) {
  emscripten_futex_wake(&word, INT32_MAX);
}

// A dynamic loop shared by the team: the next iteration to hand out, in trip counts.
struct Slot {
  std::int64_t instance = 0;  // which dynamic loop of the region (guarded by Team::slot_lock)
  std::atomic<std::int64_t> next{0};
};

struct Team {
  Micro fn = nullptr;
  int argc = 0;
  void* args[kMaxArgs] = {};
  int size = 1;
  std::atomic<std::uint32_t> generation{0};  // bumped when a region starts
  std::atomic<std::uint32_t> running{0};     // workers still inside the region
  std::atomic<std::uint32_t> arrived{0};     // at the current barrier
  std::atomic<std::uint32_t> barrier_round{0};
  std::atomic<std::int64_t> singles{0};  // single constructs claimed so far in the region
  std::mutex slot_lock;
  Slot slots[kSlots];
  int workers = 0;  // started
};

Team g_team;
std::atomic<bool> g_team_busy{false};
std::mutex g_critical;  // every critical section and reduction (one name suffices here)
std::atomic<int> g_max_threads{0};

// This thread's place: its id and team size, the nesting of regions, its construct counters.
struct Place {
  int tid = 0, size = 1, level = 0;
  std::int64_t dynamic_loops = 0, singles = 0;
};
thread_local Place tl_place;
thread_local int tl_pending_threads = 0;  // __kmpc_push_num_threads for the next fork
// The dynamic loop this thread is in.
thread_local struct {
  Slot* slot = nullptr;
  std::int64_t trips = 0, chunk = 1;
} tl_loop;
thread_local Slot tl_serial_slot;

template <std::size_t... I>
void call_with(Micro fn, std::int32_t* gtid, std::int32_t* btid, void* const* a,
               std::index_sequence<I...>) {
  using F = void (*)(std::int32_t*, std::int32_t*, decltype((void)I, (void*)nullptr)...);
  reinterpret_cast<F>(fn)(gtid, btid, a[I]...);
}

template <std::size_t... N>
void call_region(Micro fn, int argc, void* const* a, std::int32_t tid, std::index_sequence<N...>) {
  std::int32_t gtid = tid, btid = tid;
  ((argc == int(N) ? call_with(fn, &gtid, &btid, a, std::make_index_sequence<N>()) : void()), ...);
}

void run_region(Micro fn, int argc, void* const* args, int tid) {
  call_region(fn, argc, args, tid, std::make_index_sequence<kMaxArgs + 1>());
}

void* worker_main(void* arg) {
  const int tid = int(reinterpret_cast<std::intptr_t>(arg));
  std::uint32_t seen = 0;
  for (;;) {
    wait_while(g_team.generation, seen);
    seen = g_team.generation.load(std::memory_order_acquire);
    if (tid >= g_team.size) continue;
    tl_place = Place{tid, g_team.size, 1, 0, 0};
    run_region(g_team.fn, g_team.argc, g_team.args, tid);
    if (g_team.running.fetch_sub(1, std::memory_order_acq_rel) == 1) wake_all(g_team.running);
  }
  return nullptr;
}

void start_workers(int count) {
  while (g_team.workers < count) {
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, 8u << 20);  // as natively: the engine's stack frames
    pthread_t t;
    const int tid = g_team.workers + 1;
    if (pthread_create(&t, &attr, worker_main, reinterpret_cast<void*>(std::intptr_t(tid))) != 0)
      fail("cannot start a worker thread (is the page cross-origin isolated?)");
    pthread_attr_destroy(&attr);
    pthread_detach(t);
    ++g_team.workers;
  }
}

void barrier() {
  if (tl_place.size <= 1) return;
  const std::uint32_t round = g_team.barrier_round.load(std::memory_order_acquire);
  if (g_team.arrived.fetch_add(1, std::memory_order_acq_rel) + 1 == std::uint32_t(tl_place.size)) {
    g_team.arrived.store(0, std::memory_order_relaxed);
    g_team.barrier_round.fetch_add(1, std::memory_order_acq_rel);
    wake_all(g_team.barrier_round);
  } else {
    wait_while(g_team.barrier_round, round);
  }
}

// Trip count of lb, lb + st, ... up to ub inclusive (0 when empty), in the loop's own type.
template <typename T, typename ST>
std::int64_t trip_count(T lb, T ub, ST st) {
  using U = std::make_unsigned_t<T>;
  if (st > 0) return ub < lb ? 0 : std::int64_t(U(ub - lb) / U(st)) + 1;
  return lb < ub ? 0 : std::int64_t(U(lb - ub) / U(-st)) + 1;
}

constexpr std::int32_t kSchedStaticChunked = 33;
constexpr std::int32_t kSchedModifiers = (1 << 29) | (1 << 30);  // monotonic, nonmonotonic

template <typename T, typename ST>
void static_init(std::int32_t sched, std::int32_t* last, T* lower, T* upper, ST* stride, ST incr,
                 ST chunk) {
  const std::int64_t trips = trip_count(*lower, *upper, incr);
  const std::int64_t n = tl_place.size, t = tl_place.tid;
  if (last) *last = 0;
  if (trips == 0) {
    *stride = incr;
    return;
  }
  if ((sched & ~kSchedModifiers) == kSchedStaticChunked && chunk > 0) {
    // Chunks of `chunk` iterations dealt round robin; the caller adds *stride per round.
    const T first = *lower;
    *lower = T(first + T(t * chunk * incr));
    *upper = T(*lower + T((chunk - 1) * incr));
    *stride = ST(n * chunk * incr);
    if (last) *last = ((trips - 1) / chunk) % n == t;
    return;
  }
  // One block per thread, the first trips % n threads one iteration more.
  const std::int64_t small = trips / n, extra = trips % n;
  const std::int64_t begin = t * small + std::min(t, extra);
  const std::int64_t count = small + (t < extra ? 1 : 0);
  *stride = ST(trips * incr);
  if (count == 0) {  // an empty range: lower past upper
    *lower = T(*upper + T(incr));
    return;
  }
  const T first = *lower;
  *lower = T(first + T(begin * incr));
  *upper = T(*lower + T((count - 1) * incr));
  if (last) *last = begin + count == trips;
}

template <typename T, typename ST>
struct DynamicBounds {
  static thread_local T lb;
  static thread_local ST st;
};
template <typename T, typename ST>
thread_local T DynamicBounds<T, ST>::lb = 0;
template <typename T, typename ST>
thread_local ST DynamicBounds<T, ST>::st = 1;

template <typename T, typename ST>
void dispatch_init(T lb, T ub, ST st, ST chunk) {
  const std::int64_t k = ++tl_place.dynamic_loops;
  Slot* slot = &tl_serial_slot;  // serialised: this thread's own loop
  if (tl_place.size > 1) {
    slot = &g_team.slots[k % kSlots];
    const std::lock_guard<std::mutex> lock(g_team.slot_lock);
    if (slot->instance != k) {
      slot->instance = k;
      slot->next.store(0, std::memory_order_relaxed);
    }
  } else {
    slot->next.store(0, std::memory_order_relaxed);
  }
  tl_loop.slot = slot;
  tl_loop.trips = trip_count(lb, ub, st);
  tl_loop.chunk = chunk > 0 ? chunk : 1;
  DynamicBounds<T, ST>::lb = lb;
  DynamicBounds<T, ST>::st = st;
}

template <typename T, typename ST>
int dispatch_next(std::int32_t* last, T* lower, T* upper, ST* stride) {
  const std::int64_t i = tl_loop.slot->next.fetch_add(tl_loop.chunk, std::memory_order_relaxed);
  if (i >= tl_loop.trips) return 0;
  const std::int64_t end = std::min(i + tl_loop.chunk, tl_loop.trips);
  const T lb = DynamicBounds<T, ST>::lb;
  const ST st = DynamicBounds<T, ST>::st;
  *lower = T(lb + T(i * st));
  *upper = T(lb + T((end - 1) * st));
  if (stride) *stride = st;
  if (last) *last = end == tl_loop.trips;
  return 1;
}

// Regions serialised on this thread (if clause false, nested, or a second team) keep the
// enclosing place to restore.
constexpr int kMaxNesting = 16;
thread_local Place tl_saved[kMaxNesting];
thread_local int tl_saved_count = 0;

void enter_serial() {
  if (tl_saved_count == kMaxNesting) fail("parallel regions nested too deeply");
  tl_saved[tl_saved_count++] = tl_place;
  tl_place = Place{0, 1, tl_place.level + 1, 0, 0};
  tl_pending_threads = 0;
}

void leave_serial() {
  tl_place = tl_saved[--tl_saved_count];
}

int team_size_asked() {
  int n = tl_pending_threads > 0 ? tl_pending_threads : omp_get_max_threads();
  tl_pending_threads = 0;
  return std::clamp(n, 1, kMaxThreads);
}

}  // namespace

extern "C" {

struct ident_t;

std::int32_t __kmpc_global_thread_num(ident_t*) {
  return tl_place.tid;
}

void __kmpc_push_num_threads(ident_t*, std::int32_t, std::int32_t n) {
  tl_pending_threads = n;
}

void __kmpc_fork_call(ident_t*, std::int32_t argc, Micro fn, ...) {
  if (argc > kMaxArgs) fail("a parallel region captures too many variables");
  void* args[kMaxArgs];
  va_list ap;
  va_start(ap, fn);
  for (int i = 0; i < argc; ++i) args[i] = va_arg(ap, void*);
  va_end(ap);

  const int n = team_size_asked();
  if (n <= 1 || tl_place.level > 0 || g_team_busy.exchange(true, std::memory_order_acq_rel)) {
    enter_serial();
    run_region(fn, argc, args, 0);
    leave_serial();
    return;
  }
  start_workers(n - 1);
  g_team.fn = fn;
  g_team.argc = argc;
  std::copy(args, args + argc, g_team.args);
  g_team.size = n;
  g_team.singles.store(0, std::memory_order_relaxed);
  g_team.arrived.store(0, std::memory_order_relaxed);
  for (Slot& s : g_team.slots) s.instance = 0;
  g_team.running.store(std::uint32_t(n - 1), std::memory_order_relaxed);
  g_team.generation.fetch_add(1, std::memory_order_acq_rel);
  wake_all(g_team.generation);

  const Place outer = tl_place;
  tl_place = Place{0, n, 1, 0, 0};
  run_region(fn, argc, args, 0);
  tl_place = outer;
  // The region's end: every worker has left it.
  for (std::uint32_t left; (left = g_team.running.load(std::memory_order_acquire)) != 0;)
    wait_while(g_team.running, left);
  g_team_busy.store(false, std::memory_order_release);
}

void __kmpc_serialized_parallel(ident_t*, std::int32_t) {
  enter_serial();
}
void __kmpc_end_serialized_parallel(ident_t*, std::int32_t) {
  leave_serial();
}

void __kmpc_barrier(ident_t*, std::int32_t) {
  barrier();
}

std::int32_t __kmpc_master(ident_t*, std::int32_t) {
  return tl_place.tid == 0;
}
void __kmpc_end_master(ident_t*, std::int32_t) {}

std::int32_t __kmpc_single(ident_t*, std::int32_t) {
  const std::int64_t k = ++tl_place.singles;
  if (tl_place.size <= 1) return 1;
  std::int64_t expected = k - 1;
  return g_team.singles.compare_exchange_strong(expected, k, std::memory_order_acq_rel);
}
void __kmpc_end_single(ident_t*, std::int32_t) {}

void __kmpc_flush(ident_t*) {
  std::atomic_thread_fence(std::memory_order_seq_cst);
}

using kmp_critical_name = std::int32_t[8];
// The lock words clang names for reductions and unnamed critical sections: common symbols on
// other targets, which WebAssembly's object format lacks, so they are defined here (unused:
// g_critical stands for them).
kmp_critical_name maille_kmp_reduction_var __asm__(".gomp_critical_user_.reduction.var");
kmp_critical_name maille_kmp_critical_var __asm__(".gomp_critical_user_.var");
void __kmpc_critical(ident_t*, std::int32_t, kmp_critical_name*) {
  g_critical.lock();
}
void __kmpc_end_critical(ident_t*, std::int32_t, kmp_critical_name*) {
  g_critical.unlock();
}

// Reductions: every thread combines its partial value into the shared one itself, under the
// lock (libomp's "critical" method, answer 1).
std::int32_t __kmpc_reduce_nowait(ident_t*, std::int32_t, std::int32_t, std::size_t, void*,
                                  void (*)(void*, void*), kmp_critical_name*) {
  g_critical.lock();
  return 1;
}
void __kmpc_end_reduce_nowait(ident_t*, std::int32_t, kmp_critical_name*) {
  g_critical.unlock();
}
std::int32_t __kmpc_reduce(ident_t*, std::int32_t, std::int32_t, std::size_t, void*,
                           void (*)(void*, void*), kmp_critical_name*) {
  g_critical.lock();
  return 1;
}
void __kmpc_end_reduce(ident_t*, std::int32_t, kmp_critical_name*) {
  g_critical.unlock();
  barrier();
}

#define MAILLE_KMP_STATIC(suffix, T, ST)                                                           \
  void __kmpc_for_static_init_##suffix(ident_t*, std::int32_t, std::int32_t sched,                 \
                                       std::int32_t* last, T* lower, T* upper, ST* stride,         \
                                       ST incr, ST chunk) {                                        \
    static_init<T, ST>(sched, last, lower, upper, stride, incr, chunk);                            \
  }                                                                                                \
  void __kmpc_dispatch_init_##suffix(ident_t*, std::int32_t, std::int32_t, T lb, T ub, ST st,      \
                                     ST chunk) {                                                   \
    dispatch_init<T, ST>(lb, ub, st, chunk);                                                       \
  }                                                                                                \
  std::int32_t __kmpc_dispatch_next_##suffix(ident_t*, std::int32_t, std::int32_t* last, T* lower, \
                                             T* upper, ST* stride) {                               \
    return dispatch_next<T, ST>(last, lower, upper, stride);                                       \
  }                                                                                                \
  void __kmpc_dispatch_fini_##suffix(ident_t*, std::int32_t) {}

MAILLE_KMP_STATIC(4, std::int32_t, std::int32_t)
MAILLE_KMP_STATIC(4u, std::uint32_t, std::int32_t)
MAILLE_KMP_STATIC(8, std::int64_t, std::int64_t)
MAILLE_KMP_STATIC(8u, std::uint64_t, std::int64_t)
#undef MAILLE_KMP_STATIC

void __kmpc_for_static_fini(ident_t*, std::int32_t) {}

int omp_get_thread_num(void) {
  return tl_place.tid;
}
int omp_get_num_threads(void) {
  return tl_place.size;
}
int omp_get_num_procs(void) {
  return std::clamp(emscripten_num_logical_cores(), 1, kMaxThreads);
}
int omp_get_max_threads(void) {
  const int n = g_max_threads.load(std::memory_order_relaxed);
  return n > 0 ? n : omp_get_num_procs();
}
int omp_in_parallel(void) {
  return tl_place.size > 1;
}
void omp_set_num_threads(int n) {
  g_max_threads.store(std::clamp(n, 1, kMaxThreads), std::memory_order_relaxed);
}
void omp_set_dynamic(int) {}
double omp_get_wtime(void) {
  return emscripten_get_now() * 1e-3;
}

}  // extern "C"
