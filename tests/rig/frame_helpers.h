// tests/rig/frame_helpers.h: what the EvaluateJob output tests share: a fixed spread of
// activations and a two-thread parallel_for with an uneven split.
#pragma once

#include <cstdint>
#include <thread>
#include <vector>

#include "core/span.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/rig.h"

namespace mimetic::test {

// 0.3 + 0.12 (m mod 6) for muscle m: every muscle active, no two neighbours alike.
inline std::vector<float> SomeActivations(const Rig& rig) {
  std::vector<float> a(rig.muscle_count());
  for (size_t m = 0; m < a.size(); ++m) a[m] = 0.3f + 0.12f * float(m % 6);
  return a;
}

// EvaluateJob::parallel_for over two threads, split off the middle (so no range boundary
// falls where a serial run's would).
inline void TwoThreads(void*, uint32_t count, void (*task)(void*, uint32_t, uint32_t), void* data) {
  const uint32_t mid = count / 2 + 5 < count ? count / 2 + 5 : count / 2;
  std::thread t([&] { task(data, 0, mid); });
  task(data, mid, count);
  t.join();
}

// X1, the pose before the skin layers (muscles and jaw only), left in ctx->points(): a frame
// with every layer off. False when the job does not run.
inline bool RunPoseBeforeSkin(const Rig& rig, span<const float> activations, EvaluateContext* ctx) {
  std::vector<float> x1(3 * size_t(rig.vertex_count()));
  EvaluateJob plain;
  plain.rig = &rig;
  plain.context = ctx;
  plain.activations = activations;
  plain.out_positions = x1;
  plain.layers = {false, false, false};
  return plain.Run();
}

}  // namespace mimetic::test
