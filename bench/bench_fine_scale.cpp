// bench/bench_fine_scale.cpp: the fine-scale wrinkle maps of the sample head (docs/model.md
// §20-22, docs/performance.md "Fine-scale maps"), one thread:
//   BM_FineScaleMaps/<size>       MakeFineScaleMaps: both fields interpolated and rasterised,
//                                 both carvings, merge, noise, normal map (no PNG encoding)
//   BM_FineScaleCarve/<size>      the two carvings alone (CarveFurrows on prepared field images)
//   BM_FineScaleReference/<size>  the in-repo reference kernel: one pass of ReferenceBumpPass
//                                 below over a size x size height map (a plain streaming image
//                                 pass), for the ratio on a shared machine
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench/head_fixture.h"
#include "rig/offline/rig_builder.h"
#include "wrinkles/offline/fine_scale.h"

namespace mimetic {
namespace {

struct HeadFine {
  Rig rig;
  FineScaleSpec spec;
  FineScaleRigMesh mesh;
  uint32_t file_vertices = 0;
};

[[noreturn]] void Die(const Diagnostics& diag, const char* what) {
  std::fprintf(stderr, "bench_fine_scale: %s\n%s", what, diag.Format().c_str());
  std::exit(1);
}

// The sample head with the default template fitted (its default direction fields).
const HeadFine& Head() {
  static std::unique_ptr<HeadFine> h = [] {
    auto f = std::make_unique<HeadFine>();
    const bench::FittedHead fitted = bench::FitSampleHead(33741);
    const SampleHead& head = fitted.head;
    const RigSpec& spec = fitted.spec;
    Diagnostics diag;
    if (!spec.fine_scale) Die(diag, "the default template has no fine_scale block");
    if (!BuildRig(spec, head.mesh, {}, &f->rig, &diag)) Die(diag, "cannot build the head rig");
    f->spec = *spec.fine_scale;
    f->file_vertices = uint32_t(head.mesh.vertex_count());
    if (!MakeFineScaleRigMesh(f->spec, f->rig.data(), f->file_vertices, &f->mesh, &diag))
      Die(diag, "cannot make the fine-scale mesh");
    return f;
  }();
  return *h;
}

void BM_FineScaleMaps(benchmark::State& state) {
  const HeadFine& h = Head();
  FineScaleTextureOptions options;
  options.size = int(state.range(0));
  options.threads = 1;
  for (auto _ : state) {
    FineScaleMaps maps;
    Diagnostics diag;
    if (!MakeFineScaleMaps(h.spec, h.mesh.view(), h.mesh.anchor_points, options, &maps, &diag))
      state.SkipWithError("MakeFineScaleMaps failed");
    benchmark::DoNotOptimize(maps.normal.data());
  }
  state.counters["pixels"] = double(options.size) * options.size;
}

void BM_FineScaleCarve(benchmark::State& state) {
  const HeadFine& h = Head();
  const int size = int(state.range(0));
  std::vector<float2> uvs;
  Diagnostics diag;
  if (!MakeTextureSpace(h.mesh.view(), h.spec.projection, false, "fine_scale", &uvs, &diag))
    Die(diag, "texture space");
  FieldImage images[2];
  for (int f = 0; f < 2; ++f) {
    std::vector<float3> vectors, field;
    std::vector<float> weights;
    for (const DirectionAnchor& a : h.spec.fields[f].anchors) {
      vectors.push_back(a.vector);
      weights.push_back(a.weight);
    }
    if (!InterpolateDirectionField(h.mesh.view(), h.mesh.anchor_points[f], vectors, weights,
                                   h.spec.interpolation, "f", &field, &diag))
      Die(diag, "field");
    images[f] = RasterizeField(h.mesh.view(), uvs, field, size);
  }
  size_t segments = 0;
  for (auto _ : state) {
    for (int f = 0; f < 2; ++f) {
      CarveOptions o;
      o.seed = uint64_t(f);
      CarveResult r;
      CarveFurrows(images[f], o, &r);
      benchmark::DoNotOptimize(r.height.data());
      segments = r.random_starts + r.scan_starts;
    }
  }
  state.counters["furrows_field2"] = double(segments);
}

// The reference kernel: BumpNormalMap as it was on 2026-12-03 (clamped reads per texel,
// NormalizeOr, lroundf), kept here unchanged so that the reference stays one fixed amount of
// work while the library's own pass gets faster (it now gives the same bytes in about half
// the time).
std::vector<uint8_t> ReferenceBumpPass(const std::vector<float>& height, int size, float k_bump) {
  std::vector<uint8_t> out(size_t(size) * size_t(size) * 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      auto h = [&](int xx, int yy) {
        xx = std::clamp(xx, 0, size - 1);
        yy = std::clamp(yy, 0, size - 1);
        return height[size_t(yy) * size_t(size) + size_t(xx)];
      };
      const float dx = 0.5f * (h(x + 1, y) - h(x - 1, y));
      const float dy = 0.5f * (h(x, y + 1) - h(x, y - 1));
      const float3 n = NormalizeOr(float3{-k_bump * dx, k_bump * dy, 1.f}, float3{0.f, 0.f, 1.f});
      uint8_t* o = &out[3 * (size_t(y) * size_t(size) + size_t(x))];
      o[0] = uint8_t(std::lround(127.5f * (n.x + 1.f)));
      o[1] = uint8_t(std::lround(127.5f * (n.y + 1.f)));
      o[2] = uint8_t(std::lround(127.5f * (n.z + 1.f)));
    }
  return out;
}

void BM_FineScaleReference(benchmark::State& state) {
  const int size = int(state.range(0));
  std::vector<float> h(size_t(size) * size);
  for (size_t i = 0; i < h.size(); ++i) h[i] = float((i * 2654435761u) & 1023) / 1023.f;
  for (auto _ : state) {
    std::vector<uint8_t> n = ReferenceBumpPass(h, size, 1.f);
    benchmark::DoNotOptimize(n.data());
  }
}

BENCHMARK(BM_FineScaleMaps)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FineScaleCarve)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FineScaleReference)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mimetic
