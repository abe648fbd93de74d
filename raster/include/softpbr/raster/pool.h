// softpbr/raster/pool.h — the renderer's thread pool.
//
// A pool owns N−1 worker threads; the calling thread is the N-th worker. parallel_for()
// hands out indices 0..count−1 through an atomic counter, so which thread runs which index
// depends on scheduling — callers must make every index's work independent of that (one
// writer per tile). With one thread everything runs inline on the caller.
#pragma once

#include <atomic>
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
  // threads == 0 means all hardware threads.
  explicit ThreadPool(unsigned threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // Threads that run work, the caller included.
  unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // Calls fn(i) once for every i in [0, count) and returns when all calls are done.
  // The first exception thrown by fn is rethrown here after the others finish.
  void parallel_for(std::size_t count, const std::function<void(std::size_t)>& fn);

 private:
  void worker_loop();
  void run_indices();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  std::uint64_t generation_ = 0;
  unsigned active_ = 0;
  bool stop_ = false;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t count_ = 0;
  std::atomic<std::size_t> next_{0};
  std::exception_ptr error_;
};

}  // namespace softpbr::raster
