// tools/play_bake.cpp: the bake path of `mimetic play` (tools/play_bake.h).
#include "tools/play_bake.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include "core/file_util.h"
#include "expressions/runtime/clip_sample_job.h"
#include "geometry/mesh.h"
#include "io/gltf_bake.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "tools/cli.h"

namespace mimetic::tools {
namespace {

// Samples and evaluates frames [k] into `frames` (one context per worker); false when a job
// did not validate or a pose is not finite (`bad_frame` set to the first such frame).
struct Worker {
  const PlayBakeRequest* r;
  BakedFrames* frames;
  std::atomic<size_t>* next;
  std::atomic<size_t>* done;
  std::atomic<bool>* failed;
  std::vector<float>* region_weights;  // #F * #regions, when r->tension

  void operator()() const {
    const Rig& rig = *r->rig;
    const size_t nv = rig.vertex_count();
    EvaluateContext context(rig);
    std::vector<float> activations(rig.muscle_count(), 0.f);
    float jaw = 0.f;
    ClipSampleJob sample;
    sample.clip = r->clip;
    sample.out_activations = activations;
    sample.out_jaw = span<float>(&jaw, 1);
    EvaluateJob evaluate;
    evaluate.rig = &rig;
    evaluate.context = &context;
    evaluate.activations = activations;
    evaluate.layers = r->layers;
    const size_t nr = rig.tension_region_count();
    for (size_t k; !failed->load() && (k = next->fetch_add(1)) < r->times.size();) {
      sample.time = float(r->times[k]);
      evaluate.out_positions = span<float>(&frames->positions[k * nv * 3], nv * 3);
      if (r->normals) evaluate.out_normals = span<float>(&frames->normals[k * nv * 3], nv * 3);
      if (r->tension) {
        evaluate.out_tension = span<float>(&frames->tension[k * nv * 2], nv * 2);
        if (nr) evaluate.out_region_weights = span<float>(&(*region_weights)[k * nr], nr);
      }
      const bool sampled = sample.Run();
      evaluate.jaw = jaw;
      if (!sampled || !evaluate.Run()) failed->store(true);
      // The attribute holds r - 1 so that the neutral's is (0, 0) and a target's delta is the
      // frame's value minus the neutral's.
      if (r->tension)
        for (size_t v = 0; v < nv; ++v) frames->tension[(k * nv + v) * 2] -= 1.f;
      done->fetch_add(1);
    }
  }
};

}  // namespace

std::string RegionWeightsPath(const std::string& glb) {
  const std::string stem = glb.size() > 4 && glb.compare(glb.size() - 4, 4, ".glb") == 0
                               ? glb.substr(0, glb.size() - 4)
                               : glb;
  return stem + ".regions.json";
}

int PlayBake(const PlayBakeRequest& r) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const Rig& rig = *r.rig;
  const size_t nv = rig.vertex_count(), nf = r.times.size();

  BakedFrames frames;
  frames.metres_per_unit = r.metres_per_unit;
  frames.times = r.times;
  frames.positions.resize(nf * nv * 3);
  if (r.normals) frames.normals.resize(nf * nv * 3);
  // The base: the rig at zero activations (the neutral), in its output layout.
  {
    const std::vector<float> zero(rig.muscle_count(), 0.f);
    if (!PosedMesh(rig, zero, r.layers, &frames.base)) {
      std::fprintf(stderr, "mimetic play: evaluation failed (internal error: job did not "
                           "validate)\n");
      return kExitInput;
    }
    if (!r.normals) frames.base.normals.clear();
    SetDefaultEpsilons(&frames);
    if (r.tension) {
      frames.tension.resize(nf * nv * 2);
      frames.base_tension.resize(nv * 2);
      EvaluateContext context(rig);
      std::vector<float> positions(nv * 3);
      EvaluateJob neutral;
      neutral.rig = &rig;
      neutral.context = &context;
      neutral.activations = zero;
      neutral.layers = r.layers;
      neutral.out_positions = positions;
      neutral.out_tension = frames.base_tension;
      if (!neutral.Run()) {
        std::fprintf(stderr, "mimetic play: evaluation failed (internal error: job did not "
                             "validate)\n");
        return kExitInput;
      }
      for (size_t v = 0; v < nv; ++v) frames.base_tension[v * 2] -= 1.f;
    }
  }
  const size_t nr = r.tension ? size_t(rig.tension_region_count()) : 0;
  std::vector<float> region_weights(nf * nr);

  unsigned threads = r.threads ? r.threads : std::min(8u, std::max(1u, std::thread::hardware_concurrency()));
  threads = unsigned(std::min<size_t>(threads, nf));
  std::atomic<size_t> next{0}, done{0};
  std::atomic<bool> failed{false};
  const bool bar = !r.quiet && isatty(fileno(stderr)) != 0;
  auto draw = [&](size_t d, const char* what) {
    const int width = 40, filled = int(width * d / (nf ? nf : 1));
    std::fprintf(stderr, "\r[%s%s] %zu/%zu frames %s", std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), ' ').c_str(), d, nf, what);
    std::fflush(stderr);
  };
  {
    std::vector<std::thread> pool;
    const Worker worker{&r, &frames, &next, &done, &failed, &region_weights};
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    if (bar) {
      // The calling thread draws the bar and works too.
      std::thread self(worker);
      while (done.load() < nf && !failed.load()) {
        draw(done.load(), "evaluated");
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      self.join();
      draw(done.load(), "evaluated");
    } else {
      worker();
    }
    for (std::thread& t : pool) t.join();
  }
  if (failed.load()) {
    if (bar) std::fputc('\n', stderr);
    std::fprintf(stderr, "mimetic play: evaluation failed (internal error: job did not "
                         "validate); nothing was written\n");
    return kExitInput;
  }
  // Every frame finite (the offline guard that names the rig key at fault).
  for (size_t k = 0; k < nf; ++k) {
    const float* p = &frames.positions[k * nv * 3];
    const float* n = r.normals ? &frames.normals[k * nv * 3] : nullptr;
    bool finite = true;
    for (size_t i = 0; i < nv * 3 && finite; ++i)
      finite = std::isfinite(p[i]) && (!n || std::isfinite(n[i]));
    if (finite) continue;
    if (bar) std::fputc('\n', stderr);
    MeshData posed = RestMesh(rig);
    posed.positions.assign(reinterpret_cast<const float3*>(p), reinterpret_cast<const float3*>(p) + nv);
    posed.normals.assign(nv, float3{0, 0, 1});
    if (n) posed.normals.assign(reinterpret_cast<const float3*>(n), reinterpret_cast<const float3*>(n) + nv);
    std::vector<float> activations(rig.muscle_count(), 0.f);
    ClipSampleJob sample;
    sample.clip = r.clip;
    sample.time = float(r.times[k]);
    sample.out_activations = activations;
    sample.Run();
    Diagnostics bad;
    CheckPosedFinite(rig, *r.spec, activations, r.layers, posed, &bad);
    Diagnostics diag;
    diag.Append(bad, r.rig_path);
    std::fputs(diag.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic play: the posed mesh of frame %zu (t = %g s) is not finite; "
                         "nothing was written\n", k, r.times[k]);
    return kExitInput;
  }

  if (bar) draw(nf, "writing  ");
  const std::string dir = DirectoryOf(r.out);
  std::error_code ec;
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  BakeStats stats;
  Diagnostics write;
  if (!WriteBakedGlb(r.out, frames, &stats, &write)) {
    if (bar) std::fputc('\n', stderr);
    std::fputs(write.Format().c_str(), stderr);
    std::fprintf(stderr, "mimetic play: nothing was written\n");
    return kExitInput;
  }
  if (!r.regions_out.empty()) {
    Diagnostics regions;
    if (!WriteFileAtomic(r.regions_out,
                         TensionRegionsToJson(rig.tension_regions().names, r.times, region_weights),
                         &regions)) {
      if (bar) std::fputc('\n', stderr);
      std::fputs(regions.Format().c_str(), stderr);
      std::fprintf(stderr, "mimetic play: %s was written, the region weights were not\n",
                   r.out.c_str());
      return kExitInput;
    }
  }
  if (bar) {
    draw(nf, "written  ");
    std::fputc('\n', stderr);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (!r.quiet) {
    const char* end = r.clip->end() == ClipEnd::kLoop ? "loop" : "clamp";
    std::printf("played %s (%g s, %s) on %s at %g fps\n", r.clip_path.c_str(),
                double(r.clip->duration()), end, r.rig_path.c_str(), r.fps);
    std::printf("baked %zu frames (0 .. %g s) into %s: %.2f MB, %zu vertices, %zu triangles, "
                "%zu morph targets (%zu sparse; held and neutral frames share), one LINEAR "
                "weights animation\n",
                stats.frames, r.times.back(), r.out.c_str(), double(stats.bytes) / 1e6, nv,
                size_t(rig.triangle_count()), stats.targets, stats.sparse_targets);
    std::printf("vertices moved: %zu of %zu in some frame, at most %zu in one frame; took %.2f s "
                "on %u thread(s)\n", stats.moved_vertices, nv, stats.max_moved_in_frame, seconds,
                threads);
    if (r.tension)
      std::printf("tension: a _TENSION attribute (r - 1, eps) in every target%s%s\n",
                  r.regions_out.empty() ? "; the rig has no tension regions" : "; the weights of ",
                  r.regions_out.empty() ? ""
                                        : (std::to_string(rig.tension_region_count()) +
                                           " regions per frame in " + r.regions_out).c_str());
  }
  return 0;
}

}  // namespace mimetic::tools
