// bench/reference_blendshapes.h: the in-repo reference kernel, what a game does instead of
// muscles: sparse blendshapes (ARKit-style, 52 shapes) summed onto the rest pose, followed by
// the same area-weighted normal recomputation and output scatter that EvaluateJob does.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/span.h"
#include "rig/runtime/rig.h"

namespace mimetic::bench {

struct SparseShape {
  std::vector<uint32_t> indices;  // points moved by the shape, ascending
  std::vector<float3> deltas;     // one per index, at weight 1
};

// `shapes` shapes, each moving `fraction` of the rig's points, chosen by a fixed-seed
// generator (deterministic across runs and machines).
std::vector<SparseShape> MakeReferenceShapes(const Rig& rig, uint32_t shapes, float fraction);

// Scratch for one instance, sized once.
struct ReferenceContext {
  std::vector<float3> points, face_normals, point_normals;
  explicit ReferenceContext(const Rig& rig);
};

// points = rest + sum_s weights[s] * shape_s (scatter-add, shape by shape), then face normals,
// point normals, and the scatter to the file's vertex layout (stride 12 bytes).
void EvaluateReference(const Rig& rig, const std::vector<SparseShape>& shapes,
                       span<const float> weights, ReferenceContext* ctx,
                       span<float> out_positions, span<float> out_normals);

}  // namespace mimetic::bench
