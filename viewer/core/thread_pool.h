// viewer/core/thread_pool.h: a fixed set of worker threads behind EvaluateJob::parallel_for.
//
// ParallelFor cuts [0, count) into chunks of at least kMinChunk items; the caller and the workers
// take chunks from one atomic counter until none is left, and the call returns when every
// chunk has run. EvaluateJob gives the same bits however the work is split, so the pool only
// changes the time. One ParallelFor at a time (the viewer evaluates from one thread).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace mimetic::viewer {

class ThreadPool {
 public:
  // `threads` in total, the caller included (1: no worker, everything on the caller).
  explicit ThreadPool(unsigned threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned threads() const { return unsigned(workers_.size()) + 1; }
  // A ParallelForFn (rig/runtime/evaluate_job.h); `user` is the pool.
  static void ParallelFor(void* user, uint32_t count,
                          void (*task)(void* task_data, uint32_t begin, uint32_t end),
                          void* task_data);
  static constexpr uint32_t kMinChunk = 1024;

 private:
  void Run(uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* task_data);
  void WorkerLoop();
  void TakeChunks();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  uint64_t generation_ = 0;  // bumped per job (under mutex_)
  unsigned busy_ = 0;        // workers still on the current job (under mutex_)
  bool quit_ = false;
  // The current job.
  void (*task_)(void*, uint32_t, uint32_t) = nullptr;
  void* task_data_ = nullptr;
  uint32_t count_ = 0, chunk_ = 0;
  std::atomic<uint32_t> next_{0};
};

}  // namespace mimetic::viewer
