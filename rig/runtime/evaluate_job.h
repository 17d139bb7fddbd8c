// rig/runtime/evaluate_job.h: the one per-frame entry point.
//
// rest mesh + activations (+ jaw) -> positions and normals (docs/model.md §1). Run() is a fixed sequence of
// stages (static functions in evaluate_job.cpp), each reading and writing one per-frame
// FrameState (the job, the rig, its RigTables, the context's scratch and the layer flags
// resolved once per frame):
//   StageMuscles   X1 = base + sum_m a_m U_m over the active points (MusclePoints:
//                  MuscleDeformJob in SSE); base = the rest pose        docs/model.md §1-3
//   StageJaw       (rigs with a jaw, jaw > 0) each carried point turns about the hinge by its
//                  weighted angle w_p jaw range, muscle displacement included: X1 = J(X0) +
//                  R_p U = pivot + R_p (X0 + U - pivot)               docs/model.md §18
//   StageStrain    face normals of X1 with each triangle's area ratio in the same pass; the
//                  lengths of the edges the strain measures read (each edge once) docs/model.md §4-5
//   StageDisplace  per point: N1 and r gathered from its triangles; compression eps of its
//                  wrinkled-muscle rows and shrinkage s of its directional curve-wrinkle
//                  entries from the edge lengths; then X3 = X1 + d N1 with
//                  d = (1/r - 1) h  +  sum of its muscle-wrinkle rows W  +  its curve-wrinkle sum
//                                                                        docs/model.md §4-8
//                  with the fold limiter on (limit_folds), d is first bounded by a
//                  fraction of the local radius of curvature of X1 and slope-limited
//                  along edges (LimitedOffsets)                        docs/model.md §16
//   StageLimit     the fold limiter: face normals of X3; points with a triangle that the
//                  skin layers turned within kFoldLimitDot of over (against rest), and their
//                  one-ring, get their offset halved, then cut, pass after pass (after the
//                  first, a worklist: only what touches a moved point) docs/model.md §16
//   StageNormals   face normals of X3 (only when normals are requested and StageLimit did
//                  not leave them current)
//   StageOutputs   per vertex: positions scattered to the file's vertex layout, normals of X3
//                  gathered straight into the output, with strides
// StageStrain and StageDisplace run only for the layers both compiled into the rig and enabled
// in `layers`; with none, N1 is the output normal. Every stage covers the leading ranges of
// Rig::active() (points that can move, points whose normal can change, triangles touching a
// moving point), which the builder decides in ONE place (rig_builder MovingPoints) and every
// table of RigTables derives from.
//   StageTension   (only when a tension output is requested, docs/tension.md) per point the
//                  compression eps of its wrinkled-muscle rows (their largest) from the edge
//                  lengths of X1; per tension region its weight from the area ratios r of X1
//                                                                        docs/model.md §19
//   StageFineScale (only when out_fine_amplitudes is requested and the rig has fine-scale
//                  probes) per point the shrinkage s across each fine-scale field (000 eq. 4)
//                  on X1 and its amplitude M(s) (000 eq. 5)              docs/model.md §23
// With a tension output requested and no skin layer running, StageStrain still measures r (and
// the edge lengths) on X1 when the rig kept its rest areas; nothing moves for it.
// Where the next features go (each a local change):
//   - per-vertex outputs: an optional strided span on the job, its per-point values kept in a
//     context buffer named in FrameState, and one more write in StageOutputs' per-vertex loop
//     (out_tension and out_fine_amplitudes are two).
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

// Per-instance, per-frame scratch, sized once for one rig (allocation happens here, never in
// Run()). Everything that depends on the rig only lives in the rig (Rig::tables()).
class EvaluateContext {
 public:
  EvaluateContext() = default;
  explicit EvaluateContext(const Rig& rig) { Resize(rig); }
  // (Re)sizes every buffer for `rig`. The only allocating call.
  void Resize(const Rig& rig);
  // True when this context was sized for `rig` and the rig's tables passed the check
  // Rig::Build made (every index in range, every CSR well formed), which lets Run() use its
  // tables without per-frame index checks.
  bool IsFor(const Rig& rig) const;

  // Read access to the last frame's intermediate results (for overlays and tests).
  span<const float> activations() const { return activations_; }
  float jaw() const { return jaw_; }
  span<const float3> points() const { return span<const float3>(points_).first(point_count_); }
  // Per-point area ratio r of the last frame (docs/model.md §4); 1 where no skin layer ran
  // and no tension output was requested.
  span<const float> area_ratios() const { return point_ratios_; }
  // Per-point compression eps of the last frame that requested out_tension (docs/tension.md):
  // the largest eps of the point's wrinkled-muscle rows, 0 for a point without any.
  span<const float> compressions() const { return point_compressions_; }
  // Per-point fine-scale amplitudes of the last frame that requested out_fine_amplitudes
  // (docs/model.md §23), two per point (field 1, field 2); r where nothing was measured, 0 on
  // a rig without fine-scale probes.
  span<const float> fine_amplitudes() const { return point_fine_; }
  // Points whose skin-layer offset the fold limiter reduced in the last frame (docs/model.md
  // §16), and the limiter's passes (0 when it did not run).
  uint32_t limited_point_count() const { return limited_points_; }
  uint32_t limiter_passes() const { return limiter_passes_; }

  // Bytes this context holds: sizeof(EvaluateContext) plus the capacity of every vector.
  size_t ByteSize() const;

 private:
  friend struct EvaluateJob;
  uint64_t rig_uid_ = 0;
  uint32_t point_count_ = 0, triangle_count_ = 0, muscle_count_ = 0;
  std::vector<float> activations_;     // #muscles, sanitised, in [0, 1]
  std::vector<float> wrinkle_gates_;   // #muscles: this frame's wrinkle gate G per muscle, 1
                                       // for a muscle without wrinkles or gate (docs/model.md §6)
  float jaw_ = 0.f;                    // the last frame's jaw value, sanitised, in [0, 1]
  std::vector<float3> points_;         // #P deformed (rest where nothing moves), then
                                       // kPointPadFloats (face_kernels.h); mesh units
  std::vector<float4> faces_;          // #T face normals (xyz, unnormalised) and area ratios
                                       // (w); rest normals where nothing moves
  std::vector<float> point_ratios_;    // #P: area ratio r, >= 0
  std::vector<float> point_compressions_;  // #P: eps of StageTension, 0 without rows
  std::vector<float> point_fine_;      // 2 #P: fine-scale amplitudes (StageFineScale)
  std::vector<float4> point_sums_;     // #P: gathered face slots (StageDisplace)
  std::vector<float> edge_lengths_;    // RigTables::edge_count() + fine_edge_count() + 1:
                                       // this frame's, mesh units (the last is always 1: the
                                       // slot of RigTables::fine_probe_edges' missing sides)
  std::vector<float> wrinkle_offsets_; // #P: summed wrinkle displacement of the points in
                                       // RigTables::wrinkle_points this frame, mesh units
  std::vector<float> thickness_a_;     // #P: thickness offsets, slope-limit ping-pong (StageDisplace)
  std::vector<float> thickness_b_;     // #P
  std::vector<float3> skin_base_;      // #P: X1, kept for the fold limiter (StageLimit)
  std::vector<float3> skin_full_;      // #P: X3 before the limiter, of the points it reduced
  std::vector<uint8_t> limit_levels_;  // #P: how often the limiter reduced the point's offset
  std::vector<float> fold_limits_;     // #T: the limiter's cosine limit per triangle this frame
  std::vector<uint8_t> limit_flags_;   // #P: points with a triangle past its limit (one pass)
  std::vector<float> slope_min_bounds_;  // #P: kOffsetSlope * min_q |X1q - X1p| (fold limiter)
  std::vector<float> limit_edge_lengths_;  // RigTables::neighbor_edge_count(): |X1q - X1p|
  // The limiter's worklists (StageLimit), A = Rig::active_point_count(), AT =
  // Rig::active_triangle_count(); the marks are all 0 between its phases.
  std::vector<uint32_t> limit_moved_;    // A: points the last pass moved (front), at the cut (back)
  std::vector<uint32_t> limit_flagged_;  // A: the flagged points
  std::vector<uint32_t> limit_recheck_;  // A: points whose one-ring holds a recomputed triangle
  std::vector<uint32_t> limit_tris_;     // AT: triangles touching a moved point
  std::vector<uint8_t> limit_point_marks_;  // A
  std::vector<uint8_t> limit_tri_marks_;    // AT
  std::vector<uint8_t> limit_tri_bad_;      // AT: each triangle's verdict in the current pass
  uint32_t limited_points_ = 0, limiter_passes_ = 0;
};

// EvaluateJob::parallel_min_count's default (points or triangles; one is 10-100 ns of work).
inline constexpr uint32_t kParallelMinCount = 4096;

// A caller-supplied parallel loop: must call task(task_data, begin, end) over disjoint ranges
// that cover [0, count) and return when all have finished. nullptr = run serially.
using ParallelForFn = void (*)(void* user, uint32_t count,
                               void (*task)(void* task_data, uint32_t begin, uint32_t end),
                               void* task_data);

struct EvaluateJob {
  // False when: rig or context is null; the context was not sized for this rig;
  // activations.size() < rig->muscle_count(); out_positions is too small for
  // rig->vertex_count() vertices at out_positions_stride; out_normals is non-empty and too
  // small; out_tension is non-empty and too small for #V vertices at out_tension_stride (or
  // its stride is below 8 bytes or not a multiple of 4); out_fine_amplitudes likewise;
  // out_region_weights is non-empty and
  // holds fewer than rig->tension_region_count() floats; a stride is below 12 bytes or not a
  // multiple of 4.
  bool Validate() const;
  // Validates first; on false, outputs are untouched.
  bool Run() const;

  const Rig* rig = nullptr;
  EvaluateContext* context = nullptr;
  span<const float> activations;      // one per muscle, rig order; clamped to [0,1], NaN -> 0
  // The jaw opening (docs/model.md §18), a fraction of the rig's range: clamped to [0, 1],
  // NaN -> 0, like an activation (never a reason to refuse the job). Ignored by a rig without
  // a jaw; 0 gives the same bits as a rig without one.
  float jaw = 0.f;
  // Output positions of vertex v at floats [v * stride/4, v * stride/4 + 3); mesh units.
  span<float> out_positions;          // >= (#V - 1) * stride/4 + 3 floats
  size_t out_positions_stride = 12;   // bytes, >= 12, multiple of 4
  span<float> out_normals;            // optional (empty = skip); unit length; same layout rule
  size_t out_normals_stride = 12;     // bytes, >= 12, multiple of 4

  // Tension for engine shaders (docs/tension.md), both optional (empty = not computed, no
  // cost). They measure X1, the pose before the skin layers, whatever `layers` says:
  //   out_tension: per vertex v two floats at [v * stride/4, v * stride/4 + 2): the area ratio
  //     r of its point (docs/model.md §4: < 1 compressed, > 1 stretched; 1 on a rig without
  //     rest areas) and its compression eps (the largest of its point's wrinkled-muscle rows,
  //     docs/model.md §5: > 0 compressed along the muscle; 0 for a point without rows).
  //   out_region_weights: per tension region (Rig::tension_regions() order) its weight in
  //     [0, 1] (docs/model.md §19); regions past the rig's count are not written.
  span<float> out_tension;            // >= (#V - 1) * stride/4 + 2 floats
  size_t out_tension_stride = 8;      // bytes, >= 8, multiple of 4
  span<float> out_region_weights;     // >= rig->tension_region_count() floats

  // Fine-scale amplitudes (docs/model.md §23), optional (empty = not computed, no cost): per
  // vertex v two floats at [v * stride/4, v * stride/4 + 2), M(s1) and M(s2) of 000 eq. 5 with
  // s_k the shrinkage of X1 across fine-scale field k (> r compressed across it: the furrows
  // deepen; < r stretched: they fade; r = the rig's rest amplitude at rest). A renderer scales
  // height map k by amplitude k. 0 on a rig without fine-scale maps.
  span<float> out_fine_amplitudes;    // >= (#V - 1) * stride/4 + 2 floats
  size_t out_fine_amplitudes_stride = 8;  // bytes, >= 8, multiple of 4

  SkinLayers layers;                  // which skin layers run (default: all the rig has)
  // The fold limiter (docs/model.md §16): reduce the skin layers' offset where it would turn
  // a triangle over. On by default; off gives the layers' raw displacement (for comparison).
  bool limit_folds = true;
  // Testing and measurement only: run the fold limiter as the full scan its worklists replace
  // (every slope pass over every active point; every fold pass recomputes every active
  // triangle and tests every active point; the curvature bound tested against every
  // neighbour's normal, without the shortest-edge shortcut). The same bits.
  bool limit_folds_full_scan = false;

  ParallelForFn parallel_for = nullptr;  // optional engine scheduler
  void* parallel_for_user = nullptr;
  // Loops over fewer items than this run on the calling thread, not through parallel_for:
  // the fold limiter's later passes touch a few hundred points each, less work than handing
  // a range to another thread costs. The same bits either way (any split gives them).
  uint32_t parallel_min_count = kParallelMinCount;
};

// The fold limiter's threshold: a triangle counts as (nearly) turned over when the cosine
// between its unit normal and its rest normal is at most this (about 84 degrees).
inline constexpr float kFoldLimitDot = 0.1f;
// The skin offset's slope limit (offset change per unit of edge length at X1) and its
// passes (each reaches one ring further).
inline constexpr float kOffsetSlope = 0.5f;
// The skin offset's bound as a fraction of the local radius of curvature of X1.
inline constexpr float kOffsetCurvature = 0.25f;
inline constexpr uint32_t kOffsetSlopePasses = 4;
// Passes of the limiter: a point flagged k times moves by 2^-k of its offset, and by none from
// the kFoldLimitCutLevel-th time on.
inline constexpr uint32_t kFoldLimitPasses = 32;
inline constexpr uint32_t kFoldLimitCutLevel = 4;

// Floats needed for `count` elements of `floats` floats (3 unless told) at `stride_bytes` (0
// when count is 0).
size_t RequiredFloats(size_t count, size_t stride_bytes, size_t floats = 3);


}  // namespace mimetic
