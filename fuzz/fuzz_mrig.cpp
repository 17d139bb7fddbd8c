// fuzz/fuzz_mrig.cpp: the compiled-rig reader (ReadRigBinary: every check, then Rig::Build) on
// arbitrary bytes, and again with the checksum made right. A rig that loads is evaluated once, every layer on, to show that what the
// checks let through is safe to run. Seeds: fuzz_mrig_seed writes a small surface .mrig (run.sh).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/rig_binary.h"

namespace {

void LoadAndEvaluate(mimetic::span<const uint8_t> bytes) {
  mimetic::Rig rig;
  mimetic::RigBinaryInfo info;
  std::string error;
  if (!mimetic::ReadRigBinary(bytes, &rig, &info, &error)) return;
  if (rig.vertex_count() > (1u << 16)) return;  // keep each input fast
  mimetic::EvaluateContext ctx(rig);
  std::vector<float> act(rig.muscle_count(), 0.5f), pos(3 * size_t(rig.vertex_count())),
      nrm(3 * size_t(rig.vertex_count()));
  mimetic::EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_normals = nrm;
  (void)job.Run();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  LoadAndEvaluate(mimetic::span<const uint8_t>(data, size));
  // The same bytes with their checksum made right, so that mutations reach the section checks,
  // the decoding and Rig::Build instead of stopping at the checksum (a hostile file can always
  // carry a right checksum).
  if (size >= mimetic::kRigBinaryHeaderBytes) {
    std::vector<uint8_t> fixed(data, data + size);
    const uint64_t sum = mimetic::RigBinaryChecksum(fixed);
    for (int i = 0; i < 8; ++i) fixed[24 + i] = uint8_t(sum >> (8 * i));
    LoadAndEvaluate(fixed);
  }
  return 0;
}
