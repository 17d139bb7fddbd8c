// bench/bench_instances.cpp: many characters sharing one rig (docs/performance.md,
// "Instances").
//
// The bundled sample head (assets/head/sample_head.rig.json, loaded once, every layer on) is
// one immutable Rig; each instance is its own EvaluateContext, activation vector, jaw and
// output buffers, the way an engine holds one per character.
//
//   BM_Instances/<n>              n instances per frame, one thread: each instance gets its
//                                 own activations (a different phase of the same waves) and
//                                 is evaluated in turn. Counters: ns_per_vertex_per_instance,
//                                 rig_bytes (shared), bytes_per_instance (context + the
//                                 instance's activations and output positions and normals)
//   BM_InstancesTwoThreads/<n>    the same frames twice per iteration, once on one thread and
//                                 once over two (a persistent two-worker pool; with n = 1 the
//                                 instance's EvaluateJob splits its own work through
//                                 `parallel_for`, with n > 1 the instances are split between
//                                 the two threads, each running its jobs serially), each timed
//                                 on its own: `scaling` = one-thread time / two-thread time,
//                                 paired so machine drift hits both sides alike; the two
//                                 results are compared bit for bit (`mismatches` must be 0)
//   BM_InstancesTwoThreadsChunked/<n>  the same with the pool handing out chunks of 1/32 of
//                                 each call's range (at least one item) to whichever thread
//                                 is free (an atomic cursor, as an engine's job system does)
//                                 instead of a half to each: the per-item cost varies along
//                                 the point order (muscle and wrinkle points are clustered),
//                                 so halves leave one thread waiting
//   BM_InstancesTwoThreadsSpinning/<n>  the chunked pool whose threads poll for up to 200 us
//                                 for the next call (and the caller for the worker's end of
//                                 one) before they sleep: a frame's ~17 `parallel_for` calls
//                                 then cost no wake-ups
//   BM_InstancesTwoThreadsTwoEnded/<n>  the spinning pool claiming its chunks from the two
//                                 ends of each range (the worker from the front, the caller
//                                 from the back): each core keeps about the same points from
//                                 stage to stage
//   BM_InstancesTwoThreadsClips/<n>  the two-ended pool on poses from animation: each instance
//                                 plays the bundled clips (fear, frowning, smile, surprise) one
//                                 after another at 60 frames a second, where the others drive
//                                 every muscle on its own wave at once (a stress pose that
//                                 folds the skin far more than any expression does)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "bench/evaluate_setup.h"
#include "expressions/runtime/clip_sample_job.h"
#include "io/clip_file.h"
#include "io/expression_library.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"

namespace {

using namespace mimetic;

const Rig& HeadRig() {
  static std::unique_ptr<LoadedRig> loaded;
  if (loaded) return loaded->rig;
  loaded = std::make_unique<LoadedRig>();
  Diagnostics diag;
  const std::string path = std::string(MIMETIC_SOURCE_DIR) + "/assets/head/sample_head.rig.json";
  if (!LoadRig(path, loaded.get(), &diag)) {
    std::fprintf(stderr, "mimetic-bench: cannot load %s\n%s", path.c_str(), diag.Format().c_str());
    std::exit(1);
  }
  return loaded->rig;
}

// One character: what an engine keeps per instance of a shared rig.
struct Instance : bench::EvaluateSetup {
  explicit Instance(const Rig& rig) : EvaluateSetup(rig) {}
  // Instance i's pose at `frame`: the same waves as bench_evaluate.cpp, shifted per instance so
  // no two instances share a pose.
  void Pose(uint32_t frame, uint32_t i) {
    for (size_t m = 0; m < activations.size(); ++m)
      activations[m] = 0.5f + 0.5f * std::sin(0.1f * float(frame + 7 * m + 31 * i));
    job.jaw = !job.rig->jaw().empty() ? 0.5f + 0.5f * std::sin(0.07f * float(frame + 17 * i)) : 0.f;
  }
  size_t ByteSize() const {
    return context.ByteSize() + sizeof(Instance) +
           (activations.capacity() + positions.capacity() + normals.capacity()) * sizeof(float);
  }
};

// The bundled clips (assets/clips: fear, frowning, smile, surprise, 2.5 s each, built on the
// sample head with the default expression library), for poses that real animation makes
// instead of every muscle on a wave at once.
const std::vector<CompiledClip>& HeadClips() {
  static std::vector<CompiledClip> clips;
  if (!clips.empty()) return clips;
  const std::string dir = std::string(MIMETIC_SOURCE_DIR) + "/assets/";
  Diagnostics diag;
  std::vector<Expression> library;
  if (!LoadExpressionLibrary(dir + "expressions/default.library.json", &library, &diag)) {
    std::fprintf(stderr, "mimetic-bench: %s", diag.Format().c_str());
    std::exit(1);
  }
  for (const char* name : {"fear", "frowning", "smile", "surprise"}) {
    ClipSpec spec;
    CompiledClip clip;
    if (!LoadClip(dir + "clips/" + name + ".clip.json", &spec, &diag) ||
        !BuildClip(spec, HeadRig().muscle_names(), library, &clip, &diag)) {
      std::fprintf(stderr, "mimetic-bench: clip %s\n%s", name, diag.Format().c_str());
      std::exit(1);
    }
    clips.push_back(std::move(clip));
  }
  return clips;
}

// Instance i's pose at `frame` from the clips: each plays one clip after another at 60 frames
// a second (150 frames each), instance i starting with clip i mod 4.
void ClipPose(Instance* inst, uint32_t frame, uint32_t i) {
  const std::vector<CompiledClip>& clips = HeadClips();
  ClipSampleJob sample;
  sample.clip = &clips[(frame / 150 + i) % clips.size()];
  sample.time = float(frame % 150) / 60.f;
  sample.out_activations = inst->activations;
  sample.out_jaw = span<float>(&inst->job.jaw, 1);
  if (!sample.Run()) std::abort();  // built above for this rig: cannot fail
}

std::vector<std::unique_ptr<Instance>> MakeInstances(const Rig& rig, uint32_t n) {
  std::vector<std::unique_ptr<Instance>> v;
  for (uint32_t i = 0; i < n; ++i) v.push_back(std::make_unique<Instance>(rig));
  return v;
}

// A persistent pool of one extra worker: Run(count, task, data) gives the worker the first
// half of [0, count) and runs the second half on the calling thread; or, with `chunks` > 1,
// both threads claim chunks of ceil(count / chunks) items from the front of what is left
// until the range is done. An EvaluateJob's `parallel_for` calls it several times a frame, so the worker
// waits between calls instead of being started each time: on a condition variable, or, with
// `spin` > 0, first polling for up to that long (and the caller polls the same way for the
// worker's end of a call) before it sleeps, as engines' job systems do: a call that comes
// within the spin costs no wake-up. With `two_ended`, the chunks are claimed from the two
// ends of the range instead (the worker from the front, the caller from the back, until they
// meet): balanced as the cursor is, and each thread keeps about the same part of the points
// from one call to the next, so what a stage writes is mostly read by the same core in the
// next one (the work stealing of job systems, where a thread empties its own queue first).
class TwoThreadPool {
 public:
  explicit TwoThreadPool(uint32_t chunks = 1, std::chrono::microseconds spin = {},
                         bool two_ended = false)
      : chunks_(chunks), spin_(spin), two_ended_(two_ended), worker_([this] { Loop(); }) {}
  ~TwoThreadPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    wake_.notify_one();
    worker_.join();
  }
  static void ParallelFor(void* user, uint32_t count, void (*task)(void*, uint32_t, uint32_t),
                          void* data) {
    static_cast<TwoThreadPool*>(user)->Run(count, task, data);
  }
  void Run(uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
    const uint32_t mid = count / 2;
    const uint32_t chunk = chunks_ > 1 ? std::max(1u, (count + chunks_ - 1) / chunks_) : 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = task;
      data_ = data;
      end_ = mid;  // the worker's half (unless chunked)
      chunk_ = chunk;
      range_.store(uint64_t(count) << 32, std::memory_order_relaxed);  // [0, count)
      pending_ = true;
    }
    wake_.notify_one();
    if (chunk)
      Claim(task, data, chunk, !two_ended_);  // the caller from the back when two-ended
    else
      task(data, mid, count);
    Spin([this] { return !pending_; });
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return !pending_; });
  }

 private:
  // Polls `ready` for up to spin_ (a pause between polls); returns at once when spin_ is 0.
  template <class Ready>
  void Spin(const Ready& ready) const {
    if (spin_.count() == 0) return;
    const auto end = std::chrono::steady_clock::now() + spin_;
    for (uint32_t i = 1;; ++i) {
      if (ready()) return;
#if defined(__SSE2__)
      _mm_pause();
#endif
      if (i % 64 == 0 && std::chrono::steady_clock::now() > end) return;
    }
  }
  // Runs chunks of `chunk` items of what is left of the range until nothing is: range_ holds
  // [lo, hi) (lo in the low 32 bits); the front claims [lo, lo + chunk), the back
  // [hi - chunk, hi), each by one compare-and-swap.
  void Claim(void (*task)(void*, uint32_t, uint32_t), void* data, uint32_t chunk, bool front) {
    uint64_t r = range_.load(std::memory_order_relaxed);
    for (;;) {
      const uint32_t lo = uint32_t(r), hi = uint32_t(r >> 32);
      if (lo >= hi) return;
      const uint32_t b = front ? lo : (hi - lo > chunk ? hi - chunk : lo);
      const uint32_t e = front ? (hi - lo > chunk ? lo + chunk : hi) : hi;
      const uint64_t left = front ? (uint64_t(hi) << 32 | e) : (uint64_t(b) << 32 | lo);
      if (range_.compare_exchange_weak(r, left, std::memory_order_relaxed)) {
        task(data, b, e);
        r = range_.load(std::memory_order_relaxed);
      }
    }
  }
  void Loop() {
    for (;;) {
      Spin([this] { return pending_ || quit_; });
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return pending_ || quit_; });
      if (quit_) return;
      auto* task = task_;
      void* data = data_;
      const uint32_t end = end_, chunk = chunk_;
      lock.unlock();
      if (chunk)
        Claim(task, data, chunk, true);
      else if (end > 0)
        task(data, 0, end);
      lock.lock();
      pending_ = false;
      lock.unlock();
      done_.notify_one();
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  void (*task_)(void*, uint32_t, uint32_t) = nullptr;
  void* data_ = nullptr;
  uint32_t end_ = 0, chunk_ = 0;
  std::atomic<uint64_t> range_{0};  // what is left of a chunked call's range
  std::atomic<bool> pending_{false}, quit_{false};  // polled unlocked while spinning
  const uint32_t chunks_;
  const std::chrono::microseconds spin_;
  const bool two_ended_;
  std::thread worker_;
};

struct FrameWork {
  std::vector<std::unique_ptr<Instance>>* instances;
  bool ok = true;
};

// Runs instances [begin, end) of a FrameWork serially (a pool task).
void RunInstances(void* data, uint32_t begin, uint32_t end) {
  auto* w = static_cast<FrameWork*>(data);
  for (uint32_t i = begin; i < end; ++i)
    if (!(*w->instances)[i]->job.Run()) w->ok = false;
}

void SetInstanceCounters(benchmark::State& state, const Rig& rig, const Instance& one) {
  state.counters["vertices"] = rig.vertex_count();
  state.counters["rig_bytes"] = double(rig.ByteSize());
  state.counters["bytes_per_instance"] = double(one.ByteSize());
}

void BM_Instances(benchmark::State& state) {
  const Rig& rig = HeadRig();
  const uint32_t n = uint32_t(state.range(0));
  std::vector<std::unique_ptr<Instance>> instances = MakeInstances(rig, n);
  uint32_t frame = 0;
  for (auto _ : state) {
    for (uint32_t i = 0; i < n; ++i) {
      Instance& inst = *instances[i];
      inst.Pose(frame, i);
      if (!inst.job.Run()) state.SkipWithError("EvaluateJob failed");
      benchmark::DoNotOptimize(inst.positions.data());
    }
    ++frame;
  }
  SetInstanceCounters(state, rig, *instances[0]);
  state.counters["ns_per_vertex_per_instance"] = benchmark::Counter(
      double(state.iterations()) * double(n) * double(rig.vertex_count()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void TwoThreads(benchmark::State& state, uint32_t chunks,
                std::chrono::microseconds spin = {}, bool two_ended = false,
                bool clips = false) {
  const Rig& rig = HeadRig();
  if (clips) HeadClips();
  const uint32_t n = uint32_t(state.range(0));
  std::vector<std::unique_ptr<Instance>> serial = MakeInstances(rig, n);
  std::vector<std::unique_ptr<Instance>> threaded = MakeInstances(rig, n);
  TwoThreadPool pool(chunks, spin, two_ended);
  if (n == 1) {
    threaded[0]->job.parallel_for = &TwoThreadPool::ParallelFor;
    threaded[0]->job.parallel_for_user = &pool;
  }
  using Clock = std::chrono::steady_clock;
  Clock::duration one{}, two{};
  uint32_t frame = 0;
  double mismatches = 0;
  auto pose = [&](std::vector<std::unique_ptr<Instance>>& v, uint32_t f) {
    for (uint32_t i = 0; i < n; ++i) {
      if (clips)
        ClipPose(v[i].get(), f, i);
      else
        v[i]->Pose(f, i);
    }
  };
  for (auto _ : state) {
    pose(serial, frame);
    pose(threaded, frame);
    FrameWork ws{&serial}, wt{&threaded};
    const Clock::time_point t0 = Clock::now();
    RunInstances(&ws, 0, n);
    const Clock::time_point t1 = Clock::now();
    if (n == 1)
      RunInstances(&wt, 0, 1);
    else
      pool.Run(n, RunInstances, &wt);
    const Clock::time_point t2 = Clock::now();
    if (!ws.ok || !wt.ok) state.SkipWithError("EvaluateJob failed");
    one += t1 - t0;
    two += t2 - t1;
    for (uint32_t i = 0; i < n; ++i)
      if (std::memcmp(serial[i]->positions.data(), threaded[i]->positions.data(),
                      serial[i]->positions.size() * sizeof(float)) != 0 ||
          std::memcmp(serial[i]->normals.data(), threaded[i]->normals.data(),
                      serial[i]->normals.size() * sizeof(float)) != 0)
        ++mismatches;
    ++frame;
  }
  SetInstanceCounters(state, rig, *serial[0]);
  const double per = double(frame) * double(n) * double(rig.vertex_count());
  state.counters["one_thread_ns_per_vertex_per_instance"] =
      std::chrono::duration<double, std::nano>(one).count() / per;
  state.counters["two_threads_ns_per_vertex_per_instance"] =
      std::chrono::duration<double, std::nano>(two).count() / per;
  state.counters["scaling"] = double(one.count()) / double(two.count());
  state.counters["mismatches"] = mismatches;
}

void BM_InstancesTwoThreads(benchmark::State& state) { TwoThreads(state, 1); }
void BM_InstancesTwoThreadsChunked(benchmark::State& state) { TwoThreads(state, 32); }
void BM_InstancesTwoThreadsSpinning(benchmark::State& state) {
  TwoThreads(state, 32, std::chrono::microseconds(200));
}
void BM_InstancesTwoThreadsTwoEnded(benchmark::State& state) {
  TwoThreads(state, 32, std::chrono::microseconds(200), true);
}
void BM_InstancesTwoThreadsClips(benchmark::State& state) {
  TwoThreads(state, 32, std::chrono::microseconds(200), true, true);
}

}  // namespace

BENCHMARK(BM_Instances)->Arg(1)->Arg(8)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InstancesTwoThreads)
    ->Arg(1)
    ->Arg(8)
    ->Arg(64)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_InstancesTwoThreadsChunked)
    ->Arg(1)
    ->Arg(8)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_InstancesTwoThreadsSpinning)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InstancesTwoThreadsTwoEnded)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InstancesTwoThreadsClips)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
