// viewer/core/thread_pool.cpp: see thread_pool.h.
#include "viewer/core/thread_pool.h"

#include <algorithm>

namespace mimetic::viewer {

ThreadPool::ThreadPool(unsigned threads) {
  for (unsigned i = 1; i < std::max(threads, 1u); ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::ParallelFor(void* user, uint32_t count,
                             void (*task)(void* task_data, uint32_t begin, uint32_t end),
                             void* task_data) {
  static_cast<ThreadPool*>(user)->Run(count, task, task_data);
}

void ThreadPool::TakeChunks() {
  for (;;) {
    const uint32_t begin = next_.fetch_add(chunk_);
    if (begin >= count_) return;
    task_(task_data_, begin, std::min(count_, begin + chunk_));
  }
}

void ThreadPool::Run(uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* task_data) {
  if (count == 0) return;
  const uint32_t parts = threads() * 4;  // a few chunks per thread evens out uneven ranges
  const uint32_t chunk = std::max(kMinChunk, (count + parts - 1) / parts);
  if (workers_.empty() || chunk >= count) {
    task(task_data, 0, count);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = task;
    task_data_ = task_data;
    count_ = count;
    chunk_ = chunk;
    next_.store(0);
    busy_ = unsigned(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  TakeChunks();
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return busy_ == 0; });
}

void ThreadPool::WorkerLoop() {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
    }
    TakeChunks();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--busy_ == 0) done_.notify_one();
    }
  }
}

}  // namespace mimetic::viewer
