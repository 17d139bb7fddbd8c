// bench/reference_blendshapes.h: the in-repo reference kernel, what a game does instead of
// muscles: sparse blendshapes (ARKit-style, 52 shapes) summed onto the rest pose, followed by
// the same area-weighted normal recomputation and output scatter that EvaluateJob does.
//
// To be fair to it, it gets the same exact shortcut the rig uses: normals are recomputed only
// for triangles touching a point some shape moves, and only gathered at their points; the
// rest keep the rest normals.
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

struct ReferenceRig {
  std::vector<SparseShape> shapes;
  std::vector<uint32_t> triangles;  // triangles touching a moved point
  std::vector<uint32_t> points;     // points of those triangles, ascending
  std::vector<uint8_t> normal_changes;  // per point: 1 for the points above
};

// `shapes` shapes, each moving the `fraction` of the rig's points nearest to a centre drawn
// from `centres` (all points when empty), with fixed-seed random deltas (deterministic).
ReferenceRig MakeReferenceRig(const Rig& rig, uint32_t shapes, float fraction,
                              const std::vector<uint32_t>& centres = {});

// Scratch for one instance, sized once (rest positions, face normals and point normals), in
// the same layout and through the same kernels as EvaluateContext (rig/runtime/face_kernels.h:
// padded points, 16-byte face slots, SIMD face normals), so the comparison stays like for like.
struct ReferenceContext {
  std::vector<float3> points, point_normals;  // points: #P + padding
  std::vector<float4> face_normals;
  explicit ReferenceContext(const Rig& rig);
};

// points = rest + sum_s weights[s] * shape_s (scatter-add, shape by shape; the listed points
// are reset from rest first), then face normals on the listed triangles, then the output pass
// EvaluateJob does: positions scattered to the file's vertex layout, normals gathered per
// vertex where they can change (GatherFaces4), rest normals elsewhere (stride 12 bytes).
void EvaluateReference(const Rig& rig, const ReferenceRig& ref, span<const float> weights,
                       ReferenceContext* ctx, span<float> out_positions, span<float> out_normals);

}  // namespace mimetic::bench
