// The renderer's thread pool (see pool.h).
#include "softpbr/raster/pool.h"

#include <algorithm>
#include <new>
#include <system_error>

#include "softpbr/simd/simd.h"

namespace softpbr::raster {

namespace {
// Spins until done() or kSpin has passed; returns done().
template <class Done>
bool spin_until(Done done) {
  const auto deadline = std::chrono::steady_clock::now() + ThreadPool::kSpin;
  for (;;) {
    for (int i = 0; i < 64; ++i) {
      if (done()) return true;
      simd::spin_pause();
    }
    if (std::chrono::steady_clock::now() >= deadline) return done();
  }
}
}  // namespace

ThreadPool::ThreadPool(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  requested_ = threads;
  for (unsigned i = 1; i < threads; ++i) {
    try {
      workers_.emplace_back([this] { worker_loop(); });
    } catch (const std::system_error&) {
      break;  // the system refused another thread (a process or memory limit)
    } catch (const std::bad_alloc&) {
      break;  // no memory for the thread list; no thread was started by this call
    }
  }
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_.store(true, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::parallel_for(std::size_t count, const std::function<void(std::size_t)>& fn) {
  if (count == 0) return;
  if (workers_.empty() || count == 1) {
    for (std::size_t i = 0; i < count; ++i) fn(i);
    return;
  }
  // No worker is on a job here (the last call waited for all of them), so these plain
  // writes race with nothing; the generation increment publishes them.
  job_ = &fn;
  count_ = count;
  next_.store(0, std::memory_order_relaxed);
  active_.store(static_cast<unsigned>(workers_.size()), std::memory_order_relaxed);
  {
    // Under the lock, so a worker deciding to sleep either sees the new generation in its
    // wait predicate or is already waiting when notify_all() runs.
    std::lock_guard lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();  // no system call when every worker is spinning
  run_indices();
  auto finished = [this] { return active_.load(std::memory_order_acquire) == 0; };
  if (!spin_until(finished)) {
    std::unique_lock lock(mutex_);
    done_.wait(lock, finished);
  }
  std::exception_ptr error;
  {
    std::lock_guard lock(mutex_);
    error = error_;
    error_ = nullptr;
  }
  job_ = nullptr;
  if (error) std::rethrow_exception(error);
}

void ThreadPool::run_indices() {
  const std::size_t count = count_;
  for (;;) {
    const std::size_t i = next_.fetch_add(1, std::memory_order_relaxed);
    if (i >= count) return;
    try {
      (*job_)(i);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void ThreadPool::worker_loop() {
  std::uint64_t seen = 0;
  for (;;) {
    auto ready = [&] {
      return stop_.load(std::memory_order_acquire) || generation_.load(std::memory_order_acquire) != seen;
    };
    if (!spin_until(ready)) {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, ready);
    }
    if (stop_.load(std::memory_order_acquire)) return;
    seen = generation_.load(std::memory_order_acquire);
    run_indices();
    if (active_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      // Under the lock, so the caller is either before its predicate check or waiting.
      std::lock_guard lock(mutex_);
      done_.notify_one();
    }
  }
}

}  // namespace softpbr::raster
