// viewer/core/rig_rebuild.cpp: see rig_rebuild.h.
#include "viewer/core/rig_rebuild.h"

namespace mimetic::viewer {

RigRebuilder::~RigRebuilder() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    pending_.reset();
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

uint64_t RigRebuilder::Request(RigSpec spec, std::shared_ptr<const MeshData> mesh) {
  uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation = ++latest_;
    pending_ = Pending{generation, std::move(spec), std::move(mesh)};  // replaces a waiting one
    if (!running_) progress_.store(0.f), stage_.store("queued");
    done_.reset();  // an older finished build is stale now
    if (!worker_.joinable()) worker_ = std::thread([this] { Loop(); });
  }
  wake_.notify_all();
  return generation;
}

void RigRebuilder::Cancel() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++latest_;  // what runs now finishes as stale
  pending_.reset();
  done_.reset();
  if (!running_) idle_.notify_all();
}

bool RigRebuilder::Take(Result* out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!done_ || done_->generation != latest_) return false;
  *out = std::move(*done_);
  done_.reset();
  return true;
}

bool RigRebuilder::busy() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return running_ || pending_.has_value();
}

double RigRebuilder::elapsed_ms() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!running_) return 0.0;
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_)
      .count();
}

void RigRebuilder::Wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return !running_ && !pending_; });
}

uint64_t RigRebuilder::requested() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

void RigRebuilder::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || pending_.has_value(); });
    if (stop_) break;
    Pending job = std::move(*pending_);
    pending_.reset();
    running_ = true;
    started_ = std::chrono::steady_clock::now();
    lock.unlock();

    if (before_build) before_build();
    auto result = std::make_unique<Result>();
    result->generation = job.generation;
    BuildOptions options;
    options.progress = [this](float done, const char* stage) {
      progress_.store(done);
      stage_.store(stage);
    };
    result->ok = BuildRig(job.spec, *job.mesh, options, &result->rig, &result->diag);
    progress_.store(1.f);
    stage_.store("done");
    result->spec = std::move(job.spec);
    const auto end = std::chrono::steady_clock::now();

    lock.lock();
    result->ms = std::chrono::duration<double, std::milli>(end - started_).count();
    running_ = false;
    if (job.generation == latest_) done_ = std::move(result);  // else stale: dropped
    if (!pending_) idle_.notify_all();
  }
  running_ = false;
  idle_.notify_all();
}

}  // namespace mimetic::viewer
