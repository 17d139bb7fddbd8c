// fuzz/fuzz_mclip_seed.cpp: writes the seed of fuzz_mclip, a small real .mclip with every
// kind of channel (muscle, a muscle pair, expressions on each layer, the jaw) and every
// interpolation:  fuzz_mclip_seed FILE.mclip   (fuzz/run.sh runs it; generated, not
// committed, so that it always has the current format).
#include <cstdio>
#include <string>
#include <vector>

#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_binary.h"

int main(int argc, char** argv) {
  using namespace mimetic;
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_mclip_seed FILE.mclip\n");
    return 2;
  }
  auto key = [](float t, float v, KeyInterp i) { return ClipKeySpec{t, v, i, KeyTangent::kAuto}; };
  ClipSpec spec;
  spec.name = "seed";
  spec.end = ClipEnd::kLoop;
  spec.channels = {
      {ClipChannelKind::kMuscle, "a", ClipLayer::kAdd,
       {key(0.f, 0.f, KeyInterp::kCubic), key(0.5f, 0.9f, KeyInterp::kLinear),
        key(1.f, 0.3f, KeyInterp::kStep)}},
      {ClipChannelKind::kMuscle, "b", ClipLayer::kAdd, {key(0.2f, 0.5f, KeyInterp::kLinear)}},
      {ClipChannelKind::kExpression, "open", ClipLayer::kAdd,
       {key(0.f, 0.f, KeyInterp::kCubic), key(1.f, 1.f, KeyInterp::kCubic)}},
      {ClipChannelKind::kExpression, "frown", ClipLayer::kMax, {key(0.3f, 0.6f, KeyInterp::kStep)}},
      {ClipChannelKind::kExpression, "pucker", ClipLayer::kOverride,
       {key(0.f, 1.f, KeyInterp::kLinear), key(2.f, 0.f, KeyInterp::kLinear)}},
      {ClipChannelKind::kMuscle, "jaw", ClipLayer::kAdd,
       {key(0.f, 0.f, KeyInterp::kCubic), key(1.5f, 0.7f, KeyInterp::kCubic)}},
  };
  const std::vector<std::string> muscles = {"a", "b_L", "b_R", "c"};
  const std::vector<ClipExpression> expressions = {
      {"open", {{"c", 0.8f}, {"jaw", 0.5f}}}, {"frown", {{"a", 0.4f}}}, {"pucker", {{"b_L", 1.f}}}};
  CompiledClip clip;
  Diagnostics diag;
  if (!BuildClip(spec, muscles, expressions, &clip, &diag)) {
    std::fprintf(stderr, "fuzz_mclip_seed: the clip does not build\n%s", diag.Format().c_str());
    return 1;
  }
  const std::string bytes = WriteClipBinary(clip);
  std::FILE* f = std::fopen(argv[1], "wb");
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
    std::fprintf(stderr, "fuzz_mclip_seed: cannot write %s\n", argv[1]);
    return 1;
  }
  std::printf("fuzz_mclip_seed: wrote %s (%zu bytes)\n", argv[1], bytes.size());
  return 0;
}
