// examples/embed/embed.cpp: an engine's view of mimetic. One compiled rig (.mrig) shared by
// several characters, one compiled clip (.mclip) each plays at its own phase, a frame loop that
// samples and evaluates every character into its own vertex buffer, and the frame time.
// Only the runtime library is linked: no JSON, glTF, image or OpenMesh code.
//
//   embed RIG.mrig CLIP.mclip [--instances N] [--frames F] [--fps R] [--dump T FILE]
//
// --dump T FILE writes character 0's positions at clip time T (one "x y z" line per vertex, as
// `mimetic play RIG CLIP --time T --out FILE.obj` writes its `v` lines) after the loop.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/rig_binary.h"

namespace {

// What an engine keeps per character: a context, its pose inputs and its vertex buffers.
struct Character {
  mimetic::EvaluateContext context;
  std::vector<float> activations, positions, normals;
  float jaw = 0.f, phase = 0.f;
};

// Samples `clip` at `time` and evaluates `c` (no allocation: every buffer was sized up front).
bool Pose(const mimetic::Rig& rig, const mimetic::CompiledClip& clip, float time, Character* c) {
  mimetic::ClipSampleJob sample;
  sample.clip = &clip;
  sample.time = time;
  sample.out_activations = c->activations;
  sample.out_jaw = mimetic::span<float>(&c->jaw, 1);
  if (!sample.Run()) return false;
  mimetic::EvaluateJob job;
  job.rig = &rig;
  job.context = &c->context;
  job.activations = c->activations;
  job.jaw = c->jaw;
  job.out_positions = c->positions;
  job.out_normals = c->normals;
  return job.Run();
}

int Usage(const char* why) {
  std::fprintf(stderr, "embed: %s\nusage: embed RIG.mrig CLIP.mclip [--instances N] [--frames F] "
                       "[--fps R] [--dump T FILE]\n", why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return Usage("expected RIG.mrig and CLIP.mclip");
  int instances = 4, frames = 60;
  double fps = 30;
  const char* dump_file = nullptr;
  float dump_time = 0.f;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    const char* v = nullptr;
    if (a == "--instances" && (v = next())) instances = std::atoi(v);
    else if (a == "--frames" && (v = next())) frames = std::atoi(v);
    else if (a == "--fps" && (v = next())) fps = std::atof(v);
    else if (a == "--dump" && (v = next()) && (dump_file = next())) dump_time = float(std::atof(v));
    else return Usage(("bad argument '" + a + "'").c_str());
  }
  if (instances < 1 || instances > 1024 || frames < 1 || !(fps > 0))
    return Usage("--instances in [1, 1024], --frames >= 1 and --fps > 0");

  // Load once (errors are values: the message names the file and what is wrong).
  mimetic::Rig rig;
  mimetic::CompiledClip clip;
  std::string error;
  if (!mimetic::LoadRigBinaryFile(argv[1], &rig, nullptr, &error) ||
      !mimetic::LoadClipBinaryFile(argv[2], &clip, &error)) {
    std::fprintf(stderr, "embed: %s\n", error.c_str());
    return 1;
  }
  if (clip.muscle_count() != rig.muscle_count()) {
    std::fprintf(stderr, "embed: %s was compiled for %u muscles; %s has %u\n", argv[2],
                 clip.muscle_count(), argv[1], rig.muscle_count());
    return 1;
  }
  const size_t floats = 3 * size_t(rig.vertex_count());
  std::vector<Character> characters(static_cast<size_t>(instances));
  for (int i = 0; i < instances; ++i) {
    Character& c = characters[size_t(i)];
    c.context.Resize(rig);  // the only allocation per character
    c.activations.assign(rig.muscle_count(), 0.f);
    c.positions.assign(floats, 0.f);
    c.normals.assign(floats, 0.f);
    c.phase = clip.duration() * float(i) / float(instances);  // each plays at its own phase
  }

  // The frame loop.
  using Clock = std::chrono::steady_clock;
  double total_ms = 0, worst_ms = 0;
  for (int f = 0; f < frames; ++f) {
    const float t = float(f / fps);
    const Clock::time_point start = Clock::now();
    for (Character& c : characters)
      if (!Pose(rig, clip, t + c.phase, &c)) {
        std::fprintf(stderr, "embed: a job did not validate (internal error)\n");
        return 1;
      }
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    total_ms += ms;
    worst_ms = ms > worst_ms ? ms : worst_ms;
  }
  std::printf("embed: %d character(s) of %u vertices on one rig, %d frames at %g fps: %.2f ms "
              "per frame (worst %.2f), %.1f ns per vertex per character\n",
              instances, rig.vertex_count(), frames, fps, total_ms / frames, worst_ms,
              1e6 * total_ms / frames / instances / rig.vertex_count());

  if (dump_file) {
    Character& c = characters[0];
    if (!Pose(rig, clip, dump_time, &c)) return 1;
    std::FILE* out = std::fopen(dump_file, "w");
    if (!out) {
      std::fprintf(stderr, "embed: cannot write %s\n", dump_file);
      return 1;
    }
    for (size_t v = 0; v < floats; v += 3)
      std::fprintf(out, "%.9g %.9g %.9g\n", c.positions[v], c.positions[v + 1], c.positions[v + 2]);
    if (std::fclose(out) != 0) return 1;
  }
  return 0;
}
