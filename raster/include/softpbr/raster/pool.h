// softpbr/raster/pool.h — the renderer's thread pool.
//
// A pool owns N−1 worker threads; the calling thread is the N-th worker. parallel_for()
// hands out indices 0..count−1 through an atomic counter, so which thread runs which index
// depends on scheduling — callers must make every index's work independent of that (one
// writer per tile). With one thread everything runs inline on the caller.
//
// A frame runs many short parallel_for() calls (the vertex stage and assembly of every
// draw), so waking a sleeping thread for each would cost more than the work: a futex wake
// takes tens of microseconds to reach a thread on a virtual machine. Workers therefore
// spin for a short while (kSpin) after a job, watching for the next one, before they
// sleep on a condition variable; the caller spins as long for the workers to finish.
// Spinning is bounded in time, so an idle pool sleeps and an oversubscribed machine
// loses at most kSpin per wait.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace softpbr::raster {

class ThreadPool {
 public:
  // How long a thread spins for the next job (or for the others to finish) before sleeping.
  static constexpr std::chrono::microseconds kSpin{100};

  // threads == 0 means all hardware threads. When the system refuses to start a thread
  // (a limit on processes, threads or address space: containers, CI runners, `ulimit -u`),
  // the pool runs with the threads it did start — the caller's thread at least — instead
  // of failing: size() is then below requested(). Results do not depend on the count.
  explicit ThreadPool(unsigned threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // Threads that run work, the caller included.
  unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }
  // Threads asked for (0 resolved to the hardware count).
  unsigned requested() const { return requested_; }

  // Calls fn(i) once for every i in [0, count) and returns when all calls are done.
  // The first exception thrown by fn is rethrown here after the others finish.
  void parallel_for(std::size_t count, const std::function<void(std::size_t)>& fn);

 private:
  void worker_loop();
  void run_indices();

  std::vector<std::thread> workers_;
  unsigned requested_ = 1;
  std::mutex mutex_;  // guards sleeping (with the condition variables) and error_
  std::condition_variable wake_;
  std::condition_variable done_;
  // A new job is published by incrementing generation_ (release) after job_ and count_
  // are written; workers read them after seeing the increment (acquire).
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<unsigned> active_{0};  // workers still on the current job
  std::atomic<bool> stop_{false};
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t count_ = 0;
  // On a cache line of its own: every index handed out writes it.
  alignas(64) std::atomic<std::size_t> next_{0};
  alignas(64) std::exception_ptr error_;
};

}  // namespace softpbr::raster
