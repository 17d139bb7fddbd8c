// bench/bench_evaluate.cpp: mimetic-bench.
//
//   BM_Evaluate/<vertices>             EvaluateJob with every layer on: 20 muscles, N1, strain,
//                                      thickness, 6 muscle-wrinkle regions, 4 curve wrinkles,
//                                      output normals, scatter
//   BM_EvaluateMusclesOnly/<vertices>  EvaluateJob with the skin layers off: muscles + normals
//   BM_Reference/<vertices>            52 sparse blendshapes x 15% of the vertices + the same
//                                      normal recomputation and scatter
//
// Both run on the same procedural surface in the same process, one thread; compare their
// ns/vertex (the `ns_per_vertex` counter). docs/performance.md records the results.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <map>
#include <memory>
#include <vector>

#include "bench/reference_blendshapes.h"
#include "rig/offline/procedural.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"

namespace {

using namespace mimetic;

struct Fixture {
  Rig rig;
  std::vector<bench::SparseShape> shapes;
};

// One rig per size, built once: a square sheet of ~`vertices` vertices, 20 muscles each
// reaching ~15% of it (the same share each reference blendshape moves).
const Fixture& GetFixture(int vertices) {
  static std::map<int, std::unique_ptr<Fixture>> cache;
  auto& slot = cache[vertices];
  if (!slot) {
    slot = std::make_unique<Fixture>();
    const uint32_t side = uint32_t(std::lround(std::sqrt(double(vertices))));
    const MeshData mesh = MakeSurfaceMesh(side, side, 100.f, 100.f, 10.f);
    RigSpec spec = MakeSurfaceRigSpec(20, 100.f, 100.f, 10.f, 0.15f, 3.f);
    // Wrinkles as on a face: 4 wrinkled muscles (forehead sheets, corrugators) and 4 curve
    // wrinkles (nasolabial, crow's feet), reaching about a quarter of the vertices (the
    // counters wrinkle_rows_per_vertex and curve_entries_per_vertex report it). No
    // refinement, so the vertex count stays the one benchmarked.
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
    if (!BuildRig(spec, mesh, {}, &slot->rig, &diag)) {
      std::fprintf(stderr, "%s", diag.Format().c_str());
      std::abort();
    }
    slot->shapes = bench::MakeReferenceShapes(slot->rig, 52, 0.15f);
  }
  return *slot;
}

void SetCounters(benchmark::State& state, const Rig& rig) {
  state.counters["vertices"] = rig.vertex_count();
  // (vertices * 1e-9 * iterations / seconds)^-1 = nanoseconds per vertex.
  state.counters["ns_per_vertex"] =
      benchmark::Counter(double(rig.vertex_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void RunEvaluate(benchmark::State& state, EvaluateLayers layers) {
  const Fixture& f = GetFixture(int(state.range(0)));
  const Rig& rig = f.rig;
  EvaluateContext context(rig);
  std::vector<float> activations(rig.muscle_count());
  std::vector<float> positions(3 * rig.vertex_count()), normals(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &context;
  job.activations = activations;
  job.out_positions = positions;
  job.out_normals = normals;
  job.layers = layers;
  uint32_t frame = 0;
  for (auto _ : state) {
    for (size_t m = 0; m < activations.size(); ++m)
      activations[m] = 0.5f + 0.5f * std::sin(0.1f * float(frame + 7 * m));
    if (!job.Run()) state.SkipWithError("EvaluateJob failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    ++frame;
  }
  SetCounters(state, rig);
  state.counters["influences_per_vertex"] =
      double(rig.muscles.entries.size()) / double(rig.point_count());
  if (layers.muscle_wrinkles) {
    size_t rows = 0;
    for (const RigMuscleWrinkles& w : rig.muscle_wrinkles) rows += w.row_count();
    state.counters["wrinkle_rows_per_vertex"] = double(rows) / double(rig.point_count());
  }
  if (layers.curve_wrinkles)
    state.counters["curve_entries_per_vertex"] =
        double(rig.curve_wrinkles.entries.size()) / double(rig.point_count());
}

void BM_Evaluate(benchmark::State& state) { RunEvaluate(state, EvaluateLayers{}); }
void BM_EvaluateMusclesOnly(benchmark::State& state) {
  RunEvaluate(state, EvaluateLayers{false, false, false});
}

void BM_Reference(benchmark::State& state) {
  const Fixture& f = GetFixture(int(state.range(0)));
  const Rig& rig = f.rig;
  bench::ReferenceContext context(rig);
  std::vector<float> weights(f.shapes.size());
  std::vector<float> positions(3 * rig.vertex_count()), normals(3 * rig.vertex_count());
  uint32_t frame = 0;
  for (auto _ : state) {
    for (size_t s = 0; s < weights.size(); ++s)
      weights[s] = 0.5f + 0.5f * std::sin(0.1f * float(frame + 7 * s));
    bench::EvaluateReference(rig, f.shapes, weights, &context, positions, normals);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    ++frame;
  }
  SetCounters(state, rig);
}

BENCHMARK(BM_Evaluate)->Arg(10000)->Arg(50000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EvaluateMusclesOnly)->Arg(10000)->Arg(50000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Reference)->Arg(10000)->Arg(50000)->Arg(100000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
