// fuzz/fuzz_mclip.cpp: the compiled-clip reader (ReadClipBinary: every check) on arbitrary
// bytes, and again with the checksum made right. A clip that loads is sampled at a few times
// (every channel, both ends, the loop's wrap) to show that what the checks let through is safe
// to run. Seeds: fuzz_mclip_seed writes a small .mclip with every kind of channel (run.sh).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/binary_sections.h"
#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"

namespace {

void LoadAndSample(mimetic::span<const uint8_t> bytes) {
  mimetic::CompiledClip clip;
  std::string error;
  if (!mimetic::ReadClipBinary(bytes, &clip, &error)) return;
  if (clip.muscle_count() > (1u << 20)) return;  // keep each input fast
  std::vector<float> act(clip.muscle_count()), jaw(1);
  mimetic::ClipSampleJob job;
  job.clip = &clip;
  job.out_activations = act;
  job.out_jaw = jaw;
  const float d = clip.duration();
  for (float t : {-1.f, 0.f, 0.37f * d, 0.5f * d, d, 1.5f * d + 0.1f, NAN}) {
    job.time = t;
    (void)job.Run();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  LoadAndSample(mimetic::span<const uint8_t>(data, size));
  // The same bytes with their checksum made right, so that mutations reach the section and
  // value checks (a hostile file can always carry a right checksum).
  if (size >= mimetic::binary::kHeaderBytes) {
    std::vector<uint8_t> fixed(data, data + size);
    const uint64_t sum = mimetic::binary::Checksum(fixed);
    for (int i = 0; i < 8; ++i) fixed[24 + i] = uint8_t(sum >> (8 * i));
    LoadAndSample(fixed);
  }
  return 0;
}
