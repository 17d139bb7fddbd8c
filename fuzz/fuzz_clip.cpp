// fuzz/fuzz_clip.cpp: the clip file reader (ParseClip) on arbitrary bytes; a clip that parses
// is built against a fixed muscle list and one expression (BuildClip) and sampled at a few
// times, each output checked to lie in [0, 1] (docs/expressions.md).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "expressions/runtime/clip_sample_job.h"
#include "io/clip_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mimetic::ClipSpec spec;
  mimetic::Diagnostics diag;
  const bool ok = mimetic::ParseClip(std::string(reinterpret_cast<const char*>(data), size),
                                     "fuzz", &spec, &diag);
  (void)diag.Format();
  if (!ok) return 0;
  const std::vector<std::string> muscles = {"m", "m_L", "m_R", "zygomatic", "frontalis_inner_L",
                                            "frontalis_inner_R"};
  mimetic::Expression smile{"mouthSmile_L", {{"zygomatic", 0.5f}, {"m", 1.f}}, {}, {}};
  mimetic::CompiledClip clip;
  if (!mimetic::BuildClip(spec, muscles, std::vector<mimetic::Expression>{smile}, &clip, &diag))
    return 0;
  float out[6];
  const float times[] = {0.f, 0.37f, clip.duration(), clip.duration() * 1.5f + 0.1f, -1.f,
                         std::numeric_limits<float>::quiet_NaN()};
  for (float t : times) {
    mimetic::ClipSampleJob job{&clip, t, out};
    if (!job.Run()) std::abort();
    for (float v : out)
      if (!(v >= 0.f && v <= 1.f)) std::abort();
  }
  return 0;
}
