// tests/capi/capi_reference.cpp: writes the inputs and the C++ reference of the C ABI's test
// (capi_test.c, ctest capi.c_abi):  capi_reference DIR SOURCE_DIR
//   DIR/surface.mrig    the test surface (assets/surface/surface.rig.json), compiled
//   DIR/surface.mclip   a clip on its muscles (a muscle pair, an expression on each layer)
//   DIR/other.mclip     the same clip compiled for a rig of another muscle count
//   DIR/reference.bin   what the C++ runtime gives, from the JSON-built rig and clip (not from
//                       the files above): u32 vertex_count, triangle_count, muscle_count,
//                       has_jaw, frame_count; u32 triangle indices[3 T]; then per frame f: f32
//                       time (f * 0.07 - 0.2 s), activations[M], jaw, positions[3 V], normals[3 V]
//                       (ClipSampleJob, then EvaluateJob with every layer the rig has);
//                       then u32 region_count and, for frames 10, 20 and 30: u32 frame,
//                       positions[3 V] with no skin layer, tension[2 V] (r, eps),
//                       region_weights[region_count]. The rig has two tension regions added
//                       here ("left": x < 0 at weight 1; "top": y > 0 at 0.5).
#include <cstdio>
#include <string>
#include <vector>

#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/rig_binary.h"

namespace {

using namespace mimetic;

constexpr int kFrames = 40;

bool Write(const std::string& path, const std::string& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  const bool ok = f && std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (f && std::fclose(f) != 0) return false;
  if (!ok) std::fprintf(stderr, "capi_reference: cannot write %s\n", path.c_str());
  return ok;
}

void Put(std::string* out, const void* p, size_t n) {
  out->append(static_cast<const char*>(p), n);
}

ClipSpec Spec() {
  auto key = [](float t, float v, KeyInterp i) { return ClipKeySpec{t, v, i, KeyTangent::kAuto}; };
  ClipSpec spec;
  spec.name = "capi";
  spec.end = ClipEnd::kLoop;
  spec.channels = {
      {ClipChannelKind::kMuscle, "zygomatic", ClipLayer::kAdd,
       {key(0.f, 0.f, KeyInterp::kCubic), key(0.8f, 0.9f, KeyInterp::kCubic),
        key(1.6f, 0.2f, KeyInterp::kLinear), key(2.2f, 0.5f, KeyInterp::kStep)}},
      {ClipChannelKind::kExpression, "raise", ClipLayer::kAdd,
       {key(0.3f, 0.f, KeyInterp::kLinear), key(1.2f, 1.f, KeyInterp::kCubic),
        key(2.f, 0.f, KeyInterp::kCubic)}},
      {ClipChannelKind::kExpression, "cap", ClipLayer::kMax, {key(1.f, 0.6f, KeyInterp::kStep)}},
  };
  return spec;
}

const std::vector<ClipExpression> kExpressions = {
    {"raise", {{"frontalis", 0.8f}}},
    {"cap", {{"zygomatic", 0.7f}, {"frontalis", 0.3f}}},
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: capi_reference DIR SOURCE_DIR\n");
    return 2;
  }
  const std::string dir = argv[1], source = argv[2];
  LoadedRig loaded;
  Diagnostics diag;
  if (!LoadRig(source + "/assets/surface/surface.rig.json", &loaded, &diag)) {
    std::fprintf(stderr, "capi_reference: the surface rig does not load\n%s",
                 diag.Format().c_str());
    return 1;
  }
  // The surface with two tension regions (they change no position).
  RigSpec spec = loaded.spec;
  TensionRegionSpec left{"left", 0.05f, {}}, top{"top", 0.1f, {}};
  for (const float3& p : loaded.mesh.positions) {
    left.weights.push_back(p.x < 0.f ? 1.f : 0.f);
    top.weights.push_back(p.y > 0.f ? 0.5f : 0.f);
  }
  spec.tension_regions = {left, top};
  Rig rig;
  if (!BuildRig(spec, loaded.mesh, {}, &rig, &diag)) {
    std::fprintf(stderr, "capi_reference: the surface rig with regions does not build\n%s",
                 diag.Format().c_str());
    return 1;
  }
  CompiledClip clip, other;
  std::vector<std::string> more = rig.muscle_names();
  more.push_back("extra");
  if (!BuildClip(Spec(), rig.muscle_names(), kExpressions, &clip, &diag) ||
      !BuildClip(Spec(), more, kExpressions, &other, &diag)) {
    std::fprintf(stderr, "capi_reference: the clip does not build\n%s", diag.Format().c_str());
    return 1;
  }
  if (!Write(dir + "/surface.mrig", WriteRigBinary(rig.data())) ||
      !Write(dir + "/surface.mclip", WriteClipBinary(clip)) ||
      !Write(dir + "/other.mclip", WriteClipBinary(other)))
    return 1;

  std::string ref;
  const uint32_t head[5] = {rig.vertex_count(), rig.triangle_count(), rig.muscle_count(),
                            rig.jaw().empty() ? 0u : 1u, uint32_t(kFrames)};
  Put(&ref, head, sizeof head);
  Put(&ref, rig.vertex_indices().data(), rig.vertex_indices().size() * sizeof(uint32_t));
  EvaluateContext context(rig);
  std::vector<float> act(rig.muscle_count()), pos(3 * size_t(rig.vertex_count())),
      nrm(3 * size_t(rig.vertex_count()));
  float jaw = 0.f;
  std::string extended;
  const uint32_t regions = rig.tension_region_count();
  Put(&extended, &regions, sizeof regions);
  std::vector<float> bare(pos.size()), tension(2 * size_t(rig.vertex_count())), weights(regions);
  for (int f = 0; f < kFrames; ++f) {
    ClipSampleJob sample;
    sample.clip = &clip;
    sample.time = float(f) * 0.07f - 0.2f;
    sample.out_activations = act;
    sample.out_jaw = span<float>(&jaw, 1);
    EvaluateJob job;
    job.rig = &rig;
    job.context = &context;
    job.activations = act;
    job.jaw = jaw;
    job.out_positions = pos;
    job.out_normals = nrm;
    if (!sample.Run() || !job.Run()) {
      std::fprintf(stderr, "capi_reference: frame %d does not run\n", f);
      return 1;
    }
    Put(&ref, &sample.time, sizeof sample.time);
    Put(&ref, act.data(), act.size() * sizeof(float));
    Put(&ref, &jaw, sizeof jaw);
    Put(&ref, pos.data(), pos.size() * sizeof(float));
    Put(&ref, nrm.data(), nrm.size() * sizeof(float));
    if (f % 10 == 0 && f > 0) {
      // The same activations with no skin layer; then the tension outputs.
      job.layers = {false, false, false};
      job.out_positions = bare;
      job.out_normals = {};
      EvaluateJob with_tension;
      with_tension.rig = &rig;
      with_tension.context = &context;
      with_tension.activations = act;
      with_tension.jaw = jaw;
      with_tension.out_positions = pos;
      with_tension.out_tension = tension;
      with_tension.out_region_weights = weights;
      if (!job.Run() || !with_tension.Run()) {
        std::fprintf(stderr, "capi_reference: frame %d's variants do not run\n", f);
        return 1;
      }
      const uint32_t index = uint32_t(f);
      Put(&extended, &index, sizeof index);
      Put(&extended, bare.data(), bare.size() * sizeof(float));
      Put(&extended, tension.data(), tension.size() * sizeof(float));
      Put(&extended, weights.data(), weights.size() * sizeof(float));
    }
  }
  ref += extended;
  if (!Write(dir + "/reference.bin", ref)) return 1;
  std::printf("capi_reference: wrote %s (%u vertices, %u muscles, %d frames)\n", dir.c_str(),
              rig.vertex_count(), rig.muscle_count(), kFrames);
  return 0;
}
