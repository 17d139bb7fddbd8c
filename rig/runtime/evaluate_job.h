// rig/runtime/evaluate_job.h: the one per-frame entry point.
//
// rest mesh + activations -> positions and normals (MODEL.md §1). Stages:
//   1. muscles (MusclePoints: MuscleDeformJob in SSE)  X1 = X + sum_m a_m U_m  MODEL.md §1-3
//   2. face normals of X1 with each triangle's area ratio in the same pass; strain of X1 vs
//      X: lengths of the edges the strain measures read (each edge once)  MODEL.md §4-5
//   3. per point: N1 and r gathered from its triangles; compression eps of its
//      wrinkled-muscle rows and shrinkage s of its directional curve-wrinkle entries from the
//      edge lengths; then X3 = X1 + d N1 with
//      d = (1/r - 1) h  +  sum of its muscle-wrinkle rows W  +  its curve-wrinkle sum
//                                                                        MODEL.md §4-8
//   4. face normals of X3
//   5. output (vertices): positions scattered to the file's vertex layout, normals of X3
//      gathered per vertex straight into the output, with strides
// Steps 2-4 run only for the layers both compiled into the rig and enabled in `layers`; with
// none, N1 is the output normal.
// The public stage jobs (FaceNormalsJob, PointNormalsJob, EdgeCompressionJob,
// DirectionalShrinkageJob, ThicknessJob, MuscleWrinkleJob, CurveWrinkleJob) compute the same
// quantities for engines that run the stages themselves; EvaluateJob fuses them (kernels in
// rig/runtime/face_kernels.h) and gives the same normals, ratios and strain bits, and
// positions equal up to the rounding of summing d before adding it.
// EvaluateJob owns no buffer; Run() allocates nothing; the same build and the same inputs
// give the same bits, however the work is split by `parallel_for`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/span.h"
#include "rig/runtime/rig.h"

namespace mimetic {

// Per-instance scratch, sized once for one rig (allocation happens here, never in Run()).
class EvaluateContext {
 public:
  EvaluateContext() = default;
  explicit EvaluateContext(const Rig& rig) { Resize(rig); }
  // (Re)sizes every buffer for `rig`. The only allocating call.
  void Resize(const Rig& rig);
  // True when this context was sized for `rig` and the rig's tables passed the one-time check
  // Resize makes (every index in range, every CSR well formed), which lets Run() use the
  // stage jobs without per-frame index checks.
  bool IsFor(const Rig& rig) const;

  // Read access to the last frame's intermediate results (for overlays and tests).
  span<const float> activations() const { return activations_; }
  span<const float3> points() const { return span<const float3>(points_).first(point_count_); }
  // Per-point area ratio r of the last frame (MODEL.md §4); 1 where no skin layer ran.
  span<const float> area_ratios() const { return point_ratios_; }

 private:
  friend struct EvaluateJob;
  bool CheckTables(const Rig& rig);
  void BuildStrainTables(const Rig& rig);
  uint64_t rig_uid_ = 0;
  bool tables_valid_ = false;
  uint32_t point_count_ = 0, triangle_count_ = 0, muscle_count_ = 0;
  std::vector<float> activations_;     // #muscles, sanitised
  std::vector<float3> points_;         // #P deformed, then kPointPadFloats (face_kernels.h)
  std::vector<float4> faces_;          // #T face normals (xyz) and area ratios (w)
  std::vector<float3> point_normals_;  // #P, rest normals (points that never change normal)
  std::vector<float> point_ratios_;    // #P
  std::vector<float4> point_sums_;     // #P: gathered face slots (Run step 3)
  // Strain, derived from the rig's wrinkle tables when the context is sized:
  std::vector<uint32_t> edge_pairs_;     // 2 per edge that a strain measure reads
  std::vector<float> edge_lengths_;      // per such edge, this frame
  // Muscle-wrinkle rows of every table, point-major (a point's rows contiguous, in rig order):
  std::vector<uint32_t> row_offsets_;    // + 1 -> entries
  std::vector<uint32_t> entry_edges_;    // per entry: its edge
  std::vector<float> entry_rest_;        // L_ij
  std::vector<float> entry_coeffs_;      // w_ij / (L_ij sum_j w_ij); 0 where L_ij <= 0
  std::vector<float> row_profiles_;      // H(w_i) At_i per row
  std::vector<uint32_t> probe_edges_;    // 4 per curve-wrinkle probe: sides' v1v2, v1v3
  // Per point that can move: its muscle-wrinkle rows (a range of the rows above) and its
  // curve-wrinkle rows (CSR).
  std::vector<uint32_t> point_row_offsets_;
  std::vector<uint32_t> point_curve_offsets_, point_curve_rows_;
  std::vector<uint32_t> wrinkle_points_;  // points with any row above, ascending
  std::vector<float> wrinkle_offsets_;    // #P: their summed wrinkle displacement this frame
};

// A caller-supplied parallel loop: must call task(task_data, begin, end) over disjoint ranges
// that cover [0, count) and return when all have finished. nullptr = run serially.
using ParallelForFn = void (*)(void* user, uint32_t count,
                               void (*task)(void* task_data, uint32_t begin, uint32_t end),
                               void* task_data);

struct EvaluateJob {
  // False when: rig or context is null; the context was not sized for this rig;
  // activations.size() < rig->muscle_count(); out_positions is too small for
  // rig->vertex_count() vertices at out_positions_stride; out_normals is non-empty and too
  // small; a stride is below 12 bytes or not a multiple of 4.
  bool Validate() const;
  // Validates first; on false, outputs are untouched.
  bool Run() const;

  const Rig* rig = nullptr;
  EvaluateContext* context = nullptr;
  span<const float> activations;      // one per muscle, rig order; clamped to [0,1], NaN -> 0
  // Output positions of vertex v at floats [v * stride/4, v * stride/4 + 3); mesh units.
  span<float> out_positions;          // >= (#V - 1) * stride/4 + 3 floats
  size_t out_positions_stride = 12;   // bytes, >= 12, multiple of 4
  span<float> out_normals;            // optional (empty = skip); unit length; same layout rule
  size_t out_normals_stride = 12;     // bytes, >= 12, multiple of 4

  SkinLayers layers;                  // which skin layers run (default: all the rig has)

  ParallelForFn parallel_for = nullptr;  // optional engine scheduler
  void* parallel_for_user = nullptr;
};

// Floats needed for `count` elements of 3 floats at `stride_bytes` (0 when count is 0).
size_t RequiredFloats(size_t count, size_t stride_bytes);

}  // namespace mimetic
