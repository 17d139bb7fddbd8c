// bench/bench_clip.cpp: clip sampling (expressions/runtime/clip_sample_job.h) against one
// evaluation of the sample head (docs/performance.md, "Clip sampling").
//
//   BM_ClipSample/<order>     ClipSampleJob on a 52-channel clip (12 muscle channels, 40
//                             expression channels with add / max / override layers; 30 keys
//                             each, step / linear / cubic in turn), on the sample head's
//                             muscles; order 0 plays forward at 60 fps, 1 backward, 2 seeks
//                             to random times
//   BM_ClipSampleVsHead       frame by frame: the sampling job, then EvaluateJob (every
//                             layer) on assets/head/sample_head.rig.json with the sampled
//                             activations, each timed on its own; the `percent` counter is
//                             100 x sampling time / evaluation time (the target:
//                             <= 1)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_sample_job.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"

namespace {

using namespace mimetic;

constexpr int kChannels = 52, kMuscleChannels = 12, kKeys = 30;
constexpr float kDuration = 10.f;

struct ClipFixture {
  LoadedRig head;
  CompiledClip clip;
};

const ClipFixture& Fixture() {
  static std::unique_ptr<ClipFixture> f;
  if (f) return *f;
  f = std::make_unique<ClipFixture>();
  Diagnostics diag;
  if (!LoadRig(std::string(MIMETIC_SOURCE_DIR) + "/assets/head/sample_head.rig.json", &f->head,
               &diag)) {
    std::fprintf(stderr, "mimetic-bench: cannot load the sample head\n%s", diag.Format().c_str());
    std::exit(1);
  }
  const std::vector<std::string>& muscles = f->head.rig.muscle_names();
  std::mt19937 rng(52);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  ClipSpec spec{"bench", kDuration, ClipEnd::kLoop, {}};
  std::vector<ClipExpression> expressions;
  for (int c = 0; c < kChannels; ++c) {
    ClipChannelSpec channel;
    if (c < kMuscleChannels) {
      channel.kind = ClipChannelKind::kMuscle;
      channel.target = muscles[size_t(c) % muscles.size()];
    } else {
      ClipExpression e{"expression_" + std::to_string(c), {}};
      for (int k = 0; k < 6; ++k) {  // six muscles each, from the whole rig
        const std::string& m = muscles[(size_t(c) * 7 + size_t(k) * 5) % muscles.size()];
        bool seen = false;
        for (const auto& a : e.activations) seen |= a.first == m;
        if (!seen) e.activations.push_back({m, unit(rng)});
      }
      expressions.push_back(e);
      channel.kind = ClipChannelKind::kExpression;
      channel.target = e.name;
      channel.layer = ClipLayer(c % 3);
    }
    for (int k = 0; k < kKeys; ++k) {
      const float t = kDuration * (float(k) + 0.8f * unit(rng)) / float(kKeys);
      channel.keys.push_back({t, unit(rng), KeyInterp((k + c) % 3), KeyTangent(k % 2)});
    }
    spec.channels.push_back(std::move(channel));
  }
  if (!BuildClip(spec, muscles, expressions, &f->clip, &diag)) {
    std::fprintf(stderr, "mimetic-bench: cannot build the clip\n%s", diag.Format().c_str());
    std::exit(1);
  }
  return *f;
}

void BM_ClipSample(benchmark::State& state) {
  const ClipFixture& f = Fixture();
  std::vector<float> activations(f.clip.muscle_count());
  ClipSampleJob job;
  job.clip = &f.clip;
  job.out_activations = activations;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> random_time(0.f, kDuration);
  const int order = int(state.range(0));
  uint32_t frame = 0;
  for (auto _ : state) {
    job.time = order == 0 ? float(frame) / 60.f
               : order == 1 ? kDuration - float(frame % 600) / 60.f
                            : random_time(rng);
    if (!job.Run()) state.SkipWithError("ClipSampleJob failed");
    benchmark::DoNotOptimize(activations.data());
    ++frame;
  }
  state.counters["channels"] = f.clip.channel_count();
  state.counters["keys"] = double(f.clip.key_times().size());
  state.counters["muscles"] = f.clip.muscle_count();
  state.counters["clip_bytes"] = double(f.clip.ByteSize());
}

void BM_ClipSampleVsHead(benchmark::State& state) {
  const ClipFixture& f = Fixture();
  const Rig& rig = f.head.rig;
  EvaluateContext context(rig);
  std::vector<float> activations(rig.muscle_count()), positions(3 * rig.vertex_count()),
      normals(3 * rig.vertex_count());
  ClipSampleJob sample;
  sample.clip = &f.clip;
  sample.out_activations = activations;
  EvaluateJob evaluate;
  evaluate.rig = &rig;
  evaluate.context = &context;
  evaluate.activations = activations;
  evaluate.out_positions = positions;
  evaluate.out_normals = normals;
  using Clock = std::chrono::steady_clock;
  Clock::duration sampling{}, evaluation{};
  // Sampling is ~1000 times faster than the clock's resolution suits: 64 samples per reading.
  constexpr int kSamples = 64;
  uint32_t frame = 0;
  for (auto _ : state) {
    const Clock::time_point t0 = Clock::now();
    for (int i = 0; i < kSamples; ++i) {
      sample.time = float(frame) / 60.f + float(i) * 1e-4f;
      if (!sample.Run()) state.SkipWithError("ClipSampleJob failed");
      benchmark::DoNotOptimize(activations.data());
    }
    const Clock::time_point t1 = Clock::now();
    if (!evaluate.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    const Clock::time_point t2 = Clock::now();
    sampling += t1 - t0;
    evaluation += t2 - t1;
    ++frame;
  }
  const double n = double(frame);
  state.counters["sample_ns"] =
      std::chrono::duration<double, std::nano>(sampling).count() / (n * kSamples);
  state.counters["evaluate_ns"] = std::chrono::duration<double, std::nano>(evaluation).count() / n;
  state.counters["percent"] =
      100.0 * double(sampling.count()) / (double(evaluation.count()) * kSamples);
  state.counters["vertices"] = rig.vertex_count();
}

double Fastest(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

BENCHMARK(BM_ClipSample)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kNanosecond)
    ->ComputeStatistics("min", Fastest);
BENCHMARK(BM_ClipSampleVsHead)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", Fastest);

}  // namespace
