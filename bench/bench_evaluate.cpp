// bench/bench_evaluate.cpp: mimetic-bench.
//
//   BM_Evaluate/<vertices>   EvaluateJob (20 muscles + area-weighted normals + scatter)
//   BM_Reference/<vertices>  52 sparse blendshapes x 15% of the vertices + the same normals
//
// Both run on the same procedural surface in the same process, one thread; compare their
// ns/vertex (the `ns_per_vertex` counter). docs/performance.md records the results.
#include <benchmark/benchmark.h>

#include <cmath>
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
    const RigSpec spec = MakeSurfaceRigSpec(20, 100.f, 100.f, 10.f, 0.15f, 3.f);
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

void BM_Evaluate(benchmark::State& state) {
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
BENCHMARK(BM_Reference)->Arg(10000)->Arg(50000)->Arg(100000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
