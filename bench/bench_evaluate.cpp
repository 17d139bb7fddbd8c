// bench/bench_evaluate.cpp: mimetic-bench. Every benchmark runs one thread; compare the
// `ns_per_vertex` counters of a pair in the same run (docs/performance.md).
//
// Synthetic sheet (the worst case: every point is driven by some muscle):
//   BM_Evaluate/<vertices>             EvaluateJob with every layer on: 20 muscles, N1,
//                                      strain, thickness, 4 wrinkled muscles, 4 curve
//                                      wrinkles, output normals, scatter
//   BM_EvaluateMusclesOnly/<vertices>  the same rig with the skin layers off
//   BM_EvaluateNoLimiter/<vertices>    every layer, the fold limiter off (EvaluateJob::limit_folds)
//   BM_Reference/<vertices>            52 sparse blendshapes x 15% of the vertices + the
//                                      same normal recomputation and scatter
// The sample head (assets/head: the default template fitted to the procedural head generated
// at about <vertices> vertices; refinement off so the count stays the one named):
//   BM_EvaluateHead/<vertices>, BM_EvaluateHeadMusclesOnly/<vertices>,
//   BM_EvaluateHeadNoLimiter/<vertices>, BM_ReferenceHead/<vertices>
//                                      (the blendshapes move balls of 15% of the head's
//                                      points centred on the face)
//   BM_EvaluateHeadJaw/<vertices>, BM_EvaluateHeadJawNoLimiter/<vertices>,
//   BM_PairedHeadJaw/<vertices>        BM_EvaluateHead(NoLimiter) and BM_PairedHead with the
//                                      fitted jaw moving too (jaw = 0.5 + 0.5 sin(0.1 (frame + 3)))
//   BM_PairedJaw/<vertices>            every layer, frame by frame without and with the jaw
//                                      moving (two contexts, the same activations); `ratio` =
//                                      with / without (the jaw issue's budget: at most 1.10)
//   BM_PairedJawNoLimiter/<vertices>   the same with the fold limiter off on both sides
//   BM_PairedEyes                      the sample head (assets/head/sample_head.rig.json)
//                                      frame by frame without its eyes block and with it (the
//                                      lids' sliding, docs/model.md §24), every layer
//                                      (EvaluateJob::limit_folds): the jaw's own cost
//   BM_PairedHeadFine/<vertices>     every layer without and with out_fine_amplitudes (the two
//                                      fine-scale amplitudes per vertex), frame by frame;
//                                      `ratio` = with / without
//   BM_EvaluateHeadHardPose/<vertices>/<pose>, BM_EvaluateHeadHardPoseFullScan/<vertices>/<pose>
//                                      every layer at one fixed pose where the fold limiter
//                                      is busy (0 Smile, 1 Fear of
//                                      assets/expressions/default.library.json, 2 every muscle
//                                      at 1); the limiter as its worklist, and as the full scan
//                                      it replaced (EvaluateJob::limit_folds_full_scan, the
//                                      same bits); counters `limiter_passes`, `limited_points`
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/evaluate_setup.h"
#include "bench/head_fixture.h"
#include "bench/reference_blendshapes.h"
#include "content/procedural.h"
#include "content/sample_head.h"
#include "fitting/fit.h"
#include "fitting/landmarks.h"
#include "fitting/muscle_template.h"
#include "io/expression_library.h"
#include "io/rig_loader.h"
#include "io/template_file.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"

namespace {

using namespace mimetic;

struct Fixture {
  Rig rig;
  bench::ReferenceRig reference;
};

void Die(const Diagnostics& diag, const char* what) {
  std::fprintf(stderr, "mimetic-bench: %s\n%s", what, diag.Format().c_str());
  std::exit(1);
}

// A square sheet of ~`vertices` vertices, 20 muscles each reaching ~15% of it (the share each
// reference blendshape moves), 4 wrinkled muscles and 4 curve wrinkles.
std::unique_ptr<Fixture> MakeSheet(int vertices) {
  auto f = std::make_unique<Fixture>();
  const uint32_t side = uint32_t(std::lround(std::sqrt(double(vertices))));
  const MeshData mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
  RigSpec spec = MakeSurfaceRigSpec(20, 100.f, 100.f, 10.f, 0.15f, 3.f);
  // Wrinkles as on a face: 4 wrinkled muscles (forehead sheets, corrugators) and 4 curve
  // wrinkles (nasolabial, crow's feet), reaching about a quarter of the vertices (the
  // counters wrinkle_rows_per_vertex and curve_entries_per_vertex report it).
  spec.muscle_wrinkles.resize(spec.muscles.size());
  for (uint32_t m = 0; m < 4; ++m) {
    MuscleWrinkleSpec w;
    w.lambda_w = 0.6f;
    w.count = 3;
    w.depth = 0.5f;
    w.shape = 0.3f;
    w.phi_c = 0.2f;
    w.h_c = 0.f;
    spec.muscle_wrinkles[m] = w;
  }
  for (int k = 0; k < 4; ++k) {
    NamedCurveWrinkle c;
    c.name = "curve_" + std::to_string(k);
    const float v = 0.15f + 0.23f * float(k);
    c.spec.control[0] = {0.35f, v};
    c.spec.control[1] = {0.45f, v + 0.03f};
    c.spec.control[2] = {0.55f, v - 0.03f};
    c.spec.control[3] = {0.65f, v};
    c.spec.depth = 1.f;
    c.spec.width = 0.8f;
    c.spec.modulation = k % 2 ? CurveWrinkleModulation::kArea : CurveWrinkleModulation::kDirectional;
    spec.curve_wrinkles.push_back(c);
  }
  spec.refinement.enabled = false;
  Diagnostics diag;
  if (!BuildRig(spec, mesh, {}, &f->rig, &diag)) Die(diag, "cannot build the sheet rig");
  f->reference = bench::MakeReferenceRig(f->rig, 52, 0.15f);
  return f;
}

// The procedural head at ~`vertices` vertices with the default template fitted to it.
std::unique_ptr<Fixture> MakeHead(int vertices) {
  auto f = std::make_unique<Fixture>();
  const bench::FittedHead fitted = bench::FitSampleHead(vertices);
  const SampleHead& head = fitted.head;
  const RigSpec& spec = fitted.spec;
  Diagnostics diag;
  if (!BuildRig(spec, head.mesh, {}, &f->rig, &diag)) Die(diag, "cannot build the head rig");
  // Blendshape regions centred on the face: points in front of the ears, between chin and brows.
  std::vector<uint32_t> face;
  for (uint32_t p = 0; p < f->rig.point_count(); ++p) {
    const float3 x = f->rig.rest_points()[p];
    if (x.z > 40.f && x.y > -110.f && x.y < 40.f) face.push_back(p);
  }
  f->reference = bench::MakeReferenceRig(f->rig, 52, 0.15f, face);
  return f;
}

const Fixture& GetFixture(bool head, int vertices) {
  static std::map<std::pair<bool, int>, std::unique_ptr<Fixture>> cache;
  auto& slot = cache[{head, vertices}];
  if (!slot) slot = head ? MakeHead(vertices) : MakeSheet(vertices);
  return *slot;
}

void SetCounters(benchmark::State& state, const Rig& rig) {
  state.counters["vertices"] = rig.vertex_count();
  // (vertices * 1e-9 * iterations / seconds)^-1 = nanoseconds per vertex.
  state.counters["ns_per_vertex"] =
      benchmark::Counter(double(rig.vertex_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Activations (or blendshape weights) of frame `frame`: smooth, different per channel.
void FillWeights(std::vector<float>* w, uint32_t frame) {
  for (size_t m = 0; m < w->size(); ++m)
    (*w)[m] = 0.5f + 0.5f * std::sin(0.1f * float(frame + 7 * m));
}

using bench::EvaluateSetup;

float JawOf(uint32_t frame, bool jaw);

void RunEvaluate(benchmark::State& state, bool head, SkinLayers layers, bool limit_folds = true,
                 bool jaw = false) {
  const Rig& rig = GetFixture(head, int(state.range(0))).rig;
  EvaluateSetup setup(rig, layers);
  setup.job.limit_folds = limit_folds;
  const EvaluateJob& job = setup.job;
  std::vector<float>& positions = setup.positions;
  std::vector<float>& normals = setup.normals;
  uint32_t frame = 0;
  double passes = 0, limited = 0;
  if (jaw && rig.jaw().empty()) state.SkipWithError("the head rig has no jaw");
  for (auto _ : state) {
    FillWeights(&setup.activations, frame);
    setup.job.jaw = JawOf(frame, jaw);
    if (!job.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    passes += setup.context.limiter_passes();
    limited += setup.context.limited_point_count();
    ++frame;
  }
  SetCounters(state, rig);
  // The fold limiter's passes and limited points, per frame on average.
  state.counters["limiter_passes"] = frame ? passes / frame : 0.0;
  state.counters["limited_points"] = frame ? limited / frame : 0.0;
  if (jaw) {
    state.counters["jaw_points"] = double(rig.jaw().points.size());
    state.counters["jaw_full_points"] =
        double(std::count(rig.jaw().weights.begin(), rig.jaw().weights.end(), 1.f));
  }
  state.counters["influences_per_vertex"] =
      double(rig.muscles().entries.size()) / double(rig.point_count());
  state.counters["active_fraction"] = double(rig.active_point_count()) / double(rig.point_count());
  if (layers.muscle_wrinkles) {
    size_t rows = 0;
    for (const RigMuscleWrinkles& w : rig.muscle_wrinkles()) rows += w.row_count();
    state.counters["wrinkle_rows_per_vertex"] = double(rows) / double(rig.point_count());
  }
  if (layers.curve_wrinkles)
    state.counters["curve_entries_per_vertex"] =
        double(rig.curve_wrinkles().entries.size()) / double(rig.point_count());
}

void RunReference(benchmark::State& state, bool head) {
  const Fixture& f = GetFixture(head, int(state.range(0)));
  const Rig& rig = f.rig;
  bench::ReferenceContext context(rig);
  std::vector<float> weights(f.reference.shapes.size());
  std::vector<float> positions(3 * rig.vertex_count()), normals(3 * rig.vertex_count());
  uint32_t frame = 0;
  for (auto _ : state) {
    FillWeights(&weights, frame);
    bench::EvaluateReference(rig, f.reference, weights, &context, positions, normals);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    ++frame;
  }
  SetCounters(state, rig);
  state.counters["active_fraction"] = double(f.reference.points.size()) / double(rig.point_count());
}

// EvaluateJob (every layer) and the reference kernel frame by frame, each timed on its own:
// the `ratio` counter is their summed times divided, so drift of a shared machine (which moves
// separate benchmarks by up to 30%) hits both sides of every pair alike. `rig_bytes` and
// `context_bytes` report Rig::ByteSize and EvaluateContext::ByteSize.
// The jaw input of frame `frame` when `jaw` (the head's fitted jaw opening and closing, as a
// clip's jaw channel would move it), else 0.
float JawOf(uint32_t frame, bool jaw) {
  return jaw ? 0.5f + 0.5f * std::sin(0.1f * float(frame + 3)) : 0.f;
}

void RunPaired(benchmark::State& state, bool head, bool jaw = false) {
  const Fixture& f = GetFixture(head, int(state.range(0)));
  const Rig& rig = f.rig;
  EvaluateSetup setup(rig, SkinLayers{});
  bench::ReferenceContext ref_context(rig);
  std::vector<float> weights(f.reference.shapes.size());
  std::vector<float>& positions = setup.positions;
  std::vector<float>& normals = setup.normals;
  using Clock = std::chrono::steady_clock;
  Clock::duration evaluate{}, reference{};
  uint32_t frame = 0;
  for (auto _ : state) {
    FillWeights(&setup.activations, frame);
    FillWeights(&weights, frame);
    setup.job.jaw = JawOf(frame, jaw);
    const Clock::time_point t0 = Clock::now();
    if (!setup.job.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    const Clock::time_point t1 = Clock::now();
    bench::EvaluateReference(rig, f.reference, weights, &ref_context, positions, normals);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    const Clock::time_point t2 = Clock::now();
    evaluate += t1 - t0;
    reference += t2 - t1;
    ++frame;
  }
  const double n = double(frame) * double(rig.vertex_count());
  state.counters["vertices"] = rig.vertex_count();
  state.counters["evaluate_ns_per_vertex"] =
      std::chrono::duration<double, std::nano>(evaluate).count() / n;
  state.counters["reference_ns_per_vertex"] =
      std::chrono::duration<double, std::nano>(reference).count() / n;
  state.counters["ratio"] = double(evaluate.count()) / double(reference.count());
  // Memory: one Rig (shared by every instance) and one EvaluateContext (per instance).
  state.counters["rig_bytes"] = double(rig.ByteSize());
  state.counters["context_bytes"] = double(setup.context.ByteSize());
}

// EvaluateJob with every layer, frame by frame on two setups of `rig`: `plain`, and `other`,
// which `vary(other, frame)` changes before each frame; each timed on its own, the same
// activations in both. Counters: `plain_ns_per_vertex`, `<name>_ns_per_vertex` and `ratio` =
// other / plain.
template <class Vary>
void RunPairedAgainstPlain(benchmark::State& state, const Rig& rig, EvaluateSetup* other,
                           const std::string& name, const Vary& vary,
                           const Rig* plain_rig = nullptr) {
  EvaluateSetup plain(plain_rig ? *plain_rig : rig, SkinLayers{});
  plain.job.limit_folds = other->job.limit_folds;
  using Clock = std::chrono::steady_clock;
  Clock::duration without{}, with{};
  uint32_t frame = 0;
  for (auto _ : state) {
    FillWeights(&plain.activations, frame);
    FillWeights(&other->activations, frame);
    vary(*other, frame);
    const Clock::time_point t0 = Clock::now();
    if (!plain.job.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(plain.positions.data());
    const Clock::time_point t1 = Clock::now();
    if (!other->job.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(other->positions.data());
    const Clock::time_point t2 = Clock::now();
    without += t1 - t0;
    with += t2 - t1;
    ++frame;
  }
  const double n = double(frame) * double(rig.vertex_count());
  state.counters["plain_ns_per_vertex"] = std::chrono::duration<double, std::nano>(without).count() / n;
  state.counters[name + "_ns_per_vertex"] = std::chrono::duration<double, std::nano>(with).count() / n;
  state.counters["ratio"] = double(with.count()) / double(without.count());
}

// docs/model.md §23: without and with the two fine-scale amplitudes per vertex
// (out_fine_amplitudes); `ratio` = with / without (the budget: at most 1.10).
void RunPairedFine(benchmark::State& state) {
  const Rig& rig = GetFixture(true, int(state.range(0))).rig;
  if (rig.fine_scale().empty()) state.SkipWithError("the head rig has no fine-scale probes");
  EvaluateSetup fine(rig, SkinLayers{});
  std::vector<float> amplitudes(2 * rig.vertex_count());
  fine.job.out_fine_amplitudes = amplitudes;
  RunPairedAgainstPlain(state, rig, &fine, "fine", [&](EvaluateSetup&, uint32_t) {
    benchmark::DoNotOptimize(amplitudes.data());
  });
  state.counters["fine_points"] = double(rig.fine_scale().point_count());
}

// docs/model.md §18: without the jaw and with it (JawOf); `ratio` = with / without. One
// benchmark instead of BM_PairedHead against BM_PairedHeadJaw: the two sides share every
// iteration, so drift of a shared machine hits both alike.
void RunPairedJaw(benchmark::State& state, bool limit_folds = true) {
  const Rig& rig = GetFixture(true, int(state.range(0))).rig;
  if (rig.jaw().empty()) state.SkipWithError("the head rig has no jaw");
  EvaluateSetup jaw(rig, SkinLayers{});
  jaw.job.limit_folds = limit_folds;
  RunPairedAgainstPlain(state, rig, &jaw, "jaw", [](EvaluateSetup& s, uint32_t frame) {
    s.job.jaw = JawOf(frame, true);
  });
  state.counters["jaw_points"] = double(rig.jaw().points.size());
}

// Activations of hard pose `pose` (0 Smile, 1 Fear, 2 every muscle at 1) on `rig`.
std::vector<float> HardPose(const Rig& rig, int pose) {
  std::vector<float> a(rig.muscle_count(), pose == 2 ? 1.f : 0.f);
  if (pose == 2) return a;
  std::vector<Expression> library;
  Diagnostics diag;
  if (!LoadExpressionLibrary(
          std::string(MIMETIC_SOURCE_DIR) + "/assets/expressions/default.library.json", &library,
          &diag))
    Die(diag, "cannot load the expression library");
  const std::string name = pose == 0 ? "Smile" : "Fear";
  for (const Expression& e : library) {
    if (e.name != name) continue;
    for (const auto& [muscle, value] : e.activations) {
      const int m = rig.FindMuscle(muscle);
      if (m < 0) Die(diag, ("no muscle " + muscle + " in the head rig").c_str());
      a[size_t(m)] = value;
    }
    return a;
  }
  Die(diag, ("no expression " + name + " in the library").c_str());
  return a;
}

// One fixed pose, every layer, every frame the same (the limiter's work is the pose's).
void RunHardPose(benchmark::State& state, bool full_scan) {
  const Rig& rig = GetFixture(true, int(state.range(0))).rig;
  EvaluateSetup setup(rig, SkinLayers{});
  setup.activations = HardPose(rig, int(state.range(1)));
  setup.job.activations = setup.activations;
  setup.job.limit_folds_full_scan = full_scan;
  for (auto _ : state) {
    if (!setup.job.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(setup.positions.data());
    benchmark::DoNotOptimize(setup.normals.data());
  }
  SetCounters(state, rig);
  state.counters["limiter_passes"] = setup.context.limiter_passes();
  state.counters["limited_points"] = setup.context.limited_point_count();
}

void BM_Evaluate(benchmark::State& s) { RunEvaluate(s, false, SkinLayers{}); }
void BM_EvaluateMusclesOnly(benchmark::State& s) {
  RunEvaluate(s, false, SkinLayers{false, false, false});
}
void BM_EvaluateNoLimiter(benchmark::State& s) { RunEvaluate(s, false, SkinLayers{}, false); }
void BM_Reference(benchmark::State& s) { RunReference(s, false); }
void BM_EvaluateHead(benchmark::State& s) { RunEvaluate(s, true, SkinLayers{}); }
void BM_EvaluateHeadJaw(benchmark::State& s) { RunEvaluate(s, true, SkinLayers{}, true, true); }
void BM_EvaluateHeadJawNoLimiter(benchmark::State& s) {
  RunEvaluate(s, true, SkinLayers{}, false, true);
}
void BM_EvaluateHeadMusclesOnly(benchmark::State& s) {
  RunEvaluate(s, true, SkinLayers{false, false, false});
}
void BM_EvaluateHeadNoLimiter(benchmark::State& s) { RunEvaluate(s, true, SkinLayers{}, false); }
void BM_ReferenceHead(benchmark::State& s) { RunReference(s, true); }
void BM_PairedSheet(benchmark::State& s) { RunPaired(s, false); }
void BM_PairedHead(benchmark::State& s) { RunPaired(s, true); }
void BM_PairedHeadJaw(benchmark::State& s) { RunPaired(s, true, true); }
void BM_PairedHeadFine(benchmark::State& s) { RunPairedFine(s); }
// docs/model.md §24: the sample head's rig with its eyes block, against the same rig data with
// the eyes cleared (the same thickness, so only StageEyes differs), the same activations each
// frame; `ratio` = with / without. The procedural heads of the other fixtures have no eyeballs.
void BM_PairedEyes(benchmark::State& state) {
  static LoadedRig* head = nullptr;
  static Rig* without = nullptr;
  if (!head) {
    head = new LoadedRig;
    Diagnostics diag;
    if (!LoadRig(std::string(MIMETIC_SOURCE_DIR) + "/assets/head/sample_head.rig.json", head, &diag))
      Die(diag, "cannot load the sample head");
    RigData data = head->rig.data();
    data.eyes = RigEyes{};
    without = new Rig;
    if (!Rig::Build(std::move(data), without)) Die(diag, "cannot build the sample head without eyes");
  }
  if (head->rig.eyes().empty()) state.SkipWithError("the sample head's rig has no eyes block");
  EvaluateSetup eyes(head->rig, SkinLayers{});
  RunPairedAgainstPlain(state, head->rig, &eyes, "eyes", [](EvaluateSetup&, uint32_t) {}, without);
  state.counters["eye_points"] = double(head->rig.eyes().points.size());
}

void BM_PairedJaw(benchmark::State& s) { RunPairedJaw(s); }
void BM_PairedJawNoLimiter(benchmark::State& s) { RunPairedJaw(s, false); }
void BM_EvaluateHeadHardPose(benchmark::State& s) { RunHardPose(s, false); }
void BM_EvaluateHeadHardPoseFullScan(benchmark::State& s) { RunHardPose(s, true); }

// The fastest repetition next to the median: on a shared machine the minimum is the least
// disturbed estimate of what the code costs.
double Fastest(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

#define MIMETIC_SIZES                                                          \
  ->Arg(10000)->Arg(50000)->Arg(100000)->Unit(benchmark::kMicrosecond)        \
      ->ComputeStatistics("min", Fastest)
BENCHMARK(BM_Evaluate) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateMusclesOnly) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateNoLimiter) MIMETIC_SIZES;
BENCHMARK(BM_Reference) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateHead) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateHeadJaw) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateHeadJawNoLimiter) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateHeadMusclesOnly) MIMETIC_SIZES;
BENCHMARK(BM_EvaluateHeadNoLimiter) MIMETIC_SIZES;
BENCHMARK(BM_ReferenceHead) MIMETIC_SIZES;
BENCHMARK(BM_PairedSheet) MIMETIC_SIZES;
BENCHMARK(BM_PairedHead) MIMETIC_SIZES;
BENCHMARK(BM_PairedHeadJaw) MIMETIC_SIZES;
BENCHMARK(BM_PairedHeadFine) MIMETIC_SIZES;
BENCHMARK(BM_PairedJaw) MIMETIC_SIZES;
BENCHMARK(BM_PairedJawNoLimiter) MIMETIC_SIZES;
BENCHMARK(BM_PairedEyes)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", Fastest);
#define MIMETIC_HARD_POSES                                                     \
  ->ArgsProduct({{10000, 50000, 100000}, {0, 1, 2}})->Unit(benchmark::kMicrosecond) \
      ->ComputeStatistics("min", Fastest)
BENCHMARK(BM_EvaluateHeadHardPose) MIMETIC_HARD_POSES;
BENCHMARK(BM_EvaluateHeadHardPoseFullScan) MIMETIC_HARD_POSES;

}  // namespace

BENCHMARK_MAIN();
