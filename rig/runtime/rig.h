// rig/runtime/rig.h: the compiled, immutable rig shared by every instance of a face.
//
// Built offline by BuildRig (rig/offline/rig_builder.h), which fills a RigData and hands it to
// Rig::Build. Geometry lives on welded "points" (one per surface position); outputs are
// written per file "vertex" (the mesh's own layout, split at UV / normal seams), each vertex
// reading its point, so a posed mesh never cracks.
//
// Immutability (ozz-style asset): a Rig is move-only and its members are private with const
// accessors; the only way to fill one is Rig::Build, which derives the per-rig tables
// (RigTables, rig_tables.cpp), checks everything once and stamps a fresh uid. An edited rig
// is therefore always a NEW rig (copy data(), edit, Build): it cannot keep the identity, the
// tables or the check of the one it came from, and contexts sized for the old one refuse it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "muscles/runtime/muscle_table.h"
#include "rig/runtime/skin_layers.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

// One muscle's wrinkling region (docs/model.md §6), fixed on the rest pose; see MuscleWrinkleJob
// and EdgeCompressionJob for the meaning of each array (rows = region points).
struct RigMuscleWrinkles {
  uint32_t muscle = 0;                    // index into the rig's muscles
  std::vector<uint32_t> points;           // rows
  std::vector<float> phase;               // w_i, mesh units
  std::vector<float> attenuation;         // At_i
  std::vector<float> profile;             // H(w_i) At_i (MuscleWrinkleProfile), per row
  std::vector<uint32_t> edge_offsets;     // rows + 1
  std::vector<uint32_t> edge_neighbors;
  std::vector<float> edge_rest_lengths;   // mesh units
  std::vector<float> edge_weights;        // |cos theta|
  float half_cycle = 0.f;                 // u, mesh units
  float furrow_depth = 0.f;               // k0, mesh units
  float shape = 0.f;                      // alpha
  float gate = 0.f;                       // activation of full amplitude, [0, 1]; 0 = no gate
                                          // (WrinkleGate, docs/model.md §6)
  uint32_t row_count() const { return uint32_t(points.size()); }
};

// Every curve wrinkle of the rig in one table (docs/model.md §7-8); see CurveWrinkleJob.
struct RigCurveWrinkles {
  std::vector<std::string> names;            // one per wrinkle
  std::vector<CurveWrinkleParams> wrinkles;  // one per wrinkle
  std::vector<uint32_t> points;              // rows
  std::vector<uint32_t> offsets;             // rows + 1
  std::vector<CurveWrinkleEntry> entries;
  std::vector<ShrinkageProbe> probes;        // one per entry
  uint32_t row_count() const { return uint32_t(points.size()); }
};

// The largest jaw opening a rig may have: 90 degrees (the rig file says range_deg <= 90), in
// radians rounded up to a float; EvaluateJob's jaw stage relies on it (its sine and cosine
// series are accurate to t = pi/2).
inline constexpr float kMaxJawRange = 1.5707964f;

// The jaw (docs/model.md §18): a hinge through the two condyles and a per-point weight. At jaw
// value j in [0, 1] a carried point p turns about the hinge by the angle w_p j range (Rodrigues'
// rotation) and then moves by w_p j translation (the condyles' glide); the muscles'
// displacement at p turns with it. Points with w_p = 0 are not listed.
struct RigJaw {
  float3 pivot{};         // a point on the hinge axis (the condyles' midpoint), mesh units
  float3 axis{};          // unit: subject's right condyle -> left one; opening = positive angle
  float range = 0.f;      // radians at jaw = 1, in (0, kMaxJawRange]
  float3 translation{};   // the condyles' glide at jaw = 1, mesh units: + w_p jaw translation
  std::vector<uint32_t> points;  // carried points, ascending, all < active points
  std::vector<float> weights;    // per entry of `points`, in (0, 1]
  bool empty() const { return points.empty(); }
};

// The eyeballs the lids slide on (docs/model.md §24): skin that rests on an eyeball keeps its
// rest distance from the eyeball's centre when the muscles or the jaw move it, so a lid slides
// over the globe instead of lifting off it. After the muscles and the jaw, a listed point p
// that moved goes to x + w_p (c + (x - c) R_p / |x - c| - x) (c its eyeball's centre, R_p its
// rest distance from c, w_p its weight). Points that no muscle or jaw moves are not listed.
struct RigEyes {
  std::vector<float3> centers;   // one per eyeball, mesh units
  std::vector<uint32_t> points;  // held points, ascending, all < active points
  std::vector<uint32_t> eyes;    // per entry of `points`: index into `centers`
  std::vector<float> radii;      // per entry: R_p = |rest_p - c|, > 0
  std::vector<float> weights;    // per entry, in (0, 1]
  bool empty() const { return points.empty(); }
};

// A tension region's default reference c0 (docs/model.md §19): its weight 1 - exp(-C / c0) is
// 0.63 at a mean area compression C of 10%.
inline constexpr float kDefaultTensionReference = 0.1f;

// Tension regions (docs/tension.md, docs/model.md §19): named masks fixed on the rest pose, whose
// per-frame weight in [0, 1] an engine blends wrinkle maps with. Region i holds the entries
// [offsets[i], offsets[i + 1]) of `points` (ascending within a region) and `weights` (in (0, 1];
// a point outside the list has weight 0).
struct RigTensionRegions {
  std::vector<std::string> names;    // one per region, unique, non-empty
  std::vector<float> references;     // c0 per region: the mean compression of weight 1 - 1/e, > 0
  std::vector<uint32_t> offsets;     // regions + 1 (empty when there is no region)
  std::vector<uint32_t> points;
  std::vector<float> weights;
  uint32_t region_count() const { return uint32_t(names.size()); }
  bool empty() const { return names.empty(); }
};

// A fine-scale amplitude's default rest value r (docs/model.md §23, 000 eq. 5): the fine
// furrows show at half their full depth at rest.
inline constexpr float kDefaultFineScaleRestAmplitude = 0.5f;

// Fine-scale amplitudes (docs/model.md §23): for each point p of [0, point_count()) two
// directional shrinkage probes (000 eq. 4), probes[2p] across field 1's texture direction and
// probes[2p + 1] across field 2's, fixed on the rest pose. EvaluateJob's out_fine_amplitudes
// reports M(s) (000 eq. 5, r = rest_amplitude) of each; points past point_count() (they and
// their triangles never move) have s = 0, M = r. Empty = the rig has no fine-scale maps.
struct RigFineScale {
  float rest_amplitude = kDefaultFineScaleRestAmplitude;  // r in [0, 1]
  std::vector<ShrinkageProbe> probes;                     // 2 per point, probe.point = p
  uint32_t point_count() const { return uint32_t(probes.size() / 2); }
  bool empty() const { return probes.empty(); }
};

// The leading ranges a frame touches (points and triangles are ordered so, see rig_builder
// MovingPoints / ActiveOrder, the one place that decides what can move): [0, points) can move;
// [0, normal_points) can change normal; the rest stay at their rest position and normal.
// Triangles [0, triangles) touch a point that can move; the others keep their rest normal.
// Every per-frame range of EvaluateJob and every per-point table of RigTables derives from it.
struct RigActiveRanges {
  uint32_t points = 0;         // active points, <= normal_points
  uint32_t normal_points = 0;  // points whose normal can change, <= #P
  uint32_t triangles = 0;      // triangles touching an active point, <= #T
};

// What the builder authors: plain, copyable, editable. Rig::Build turns it into a Rig.
struct RigData {
  // Welded surface.
  std::vector<float3> rest_points;              // #P, mesh units
  std::vector<uint32_t> triangles;              // 3 * #T, into points, counter-clockwise
  std::vector<uint32_t> point_triangle_offsets; // #P + 1 (CSR): triangles around each point
  std::vector<uint32_t> point_triangles;        // triangle indices, ascending per point
  RigActiveRanges active;                       // what a frame touches

  // The file's layout.
  std::vector<uint32_t> vertex_points;   // #V: output vertex -> point
  std::vector<uint32_t> vertex_indices;  // 3 * #T, into vertices (the file's index buffer)
  std::vector<float2> vertex_uvs;        // #V, or empty when the mesh has none

  // Skin (docs/model.md §4-8).
  // What was compiled: a layer is on when the rig file enables it and it has something to do
  // (all off until the builder says otherwise).
  SkinLayers layers{false, false, false};
  std::vector<float> point_thickness;    // #P, mesh units (docs/model.md §4)
  std::vector<float> rest_triangle_areas;  // #T, mesh units^2 (when any skin layer is on)
  float min_area_ratio = kDefaultMinAreaRatio;  // r_min (docs/model.md §4 choice)
  std::vector<RigMuscleWrinkles> muscle_wrinkles;  // one per wrinkled muscle, muscle order
  RigCurveWrinkles curve_wrinkles;

  // Muscles.
  std::vector<std::string> muscle_names;  // rig order = activation order
  MuscleTable muscles;

  // The jaw (empty = none: EvaluateJob::jaw is ignored).
  RigJaw jaw;

  // The eyeballs the lids slide on (empty = none; docs/model.md §24).
  RigEyes eyes;

  // Tension regions (empty = none). A rig with any keeps rest_triangle_areas, skin layers or
  // not, so that EvaluateJob's tension outputs can measure r.
  RigTensionRegions tension_regions;

  // Fine-scale amplitudes (empty = none): probes for the points [0, active.normal_points).
  RigFineScale fine_scale;

  uint32_t point_count() const { return uint32_t(rest_points.size()); }
  uint32_t triangle_count() const { return uint32_t(triangles.size() / 3); }
  uint32_t muscle_count() const { return uint32_t(muscle_names.size()); }
};

// Tables that depend on the rig only, derived once by Rig::Build (rig_tables.cpp) and read by
// every EvaluateJob on the rig (one copy however many instances).
struct RigTables {
  // Rest pose.
  std::vector<float4> rest_faces;          // #T: rest face normals (xyz, FaceNormals4), w = 0
  std::vector<float3> rest_point_normals;  // #P: unit rest normals (read for points that never
                                           // change normal)
  // Strain: the edges read by the compression rows and the shrinkage probes, each once.
  std::vector<uint32_t> edge_pairs;        // 2 per edge that a strain measure reads
  // Muscle-wrinkle rows of every table, point-major (a point's rows contiguous, in rig order):
  std::vector<uint32_t> row_offsets;       // rows + 1 -> entries
  std::vector<uint32_t> entry_edges;       // per entry: its edge
  std::vector<float> entry_rest;           // L_ij, mesh units
  std::vector<float> entry_coeffs;         // w_ij / (L_ij sum_j w_ij); 0 where L_ij <= 0
  std::vector<float> row_profiles;         // H(w_i) At_i per row, mesh units
  std::vector<uint32_t> row_muscles;       // per row: its muscle (index of the frame's gates)
  std::vector<uint32_t> probe_edges;       // 4 per curve-wrinkle probe: sides' v1v2, v1v3
  // Fine-scale probes' edges (docs/model.md §23) that no strain measure reads: they follow the
  // strain's edges as ids [edge_count(), edge_count() + fine_edge_count()), measured only by
  // frames that request out_fine_amplitudes (such a frame measures the strain's edges with
  // them, once: the probes read those too).
  std::vector<uint32_t> fine_edge_pairs;   // 2 per edge
  // The fine-scale probes in blocks of kFineProbeBlock (the last block padded), slot-major
  // within a block so that a block's lanes load together: per block, edges [slot][lane]
  // (slots: side 0's v1v2, v1v3, side 1's v1v2, v1v3; a side the probe lacks, or a rest length
  // that is not positive, reads edge_count() + fine_edge_count(), a length that is always 1;
  // the other ids as above: a strain edge's or edge_count() + a fine_edge_pairs index) and params
  // [kind][lane] (kinds: side 0's beta, rest v1v2, rest v1v3, side 1's the same, then the
  // probe's mean factor: 1/2 for two sides, else 1). A missing side has rest lengths 1 and
  // beta 0, so its shrinkage is 0. docs/model.md §23.
  static constexpr uint32_t kFineProbeBlock = 4;
  std::vector<uint32_t> fine_probe_edges;  // 4 * kFineProbeBlock per block
  std::vector<float> fine_probe_params;    // 7 * kFineProbeBlock per block
  // Per active point: its muscle-wrinkle rows (a range of the rows above) and its
  // curve-wrinkle rows (CSR into RigCurveWrinkles rows).
  std::vector<uint32_t> point_row_offsets;    // active points + 1
  std::vector<uint32_t> point_curve_offsets;  // active points + 1
  std::vector<uint32_t> point_curve_rows;     // curve-wrinkle rows
  std::vector<uint32_t> wrinkle_points;       // points with any row above, ascending
  // Per active point: the points it shares a triangle with, each once, ascending (the fold
  // limiter's offset bounds read them, docs/model.md §16).
  std::vector<uint32_t> point_neighbor_offsets;  // active points + 1
  std::vector<uint32_t> point_neighbors;
  // The edges p-q of those lists, each once: per slot of point_neighbors its edge, and two
  // points per edge (the limiter measures each edge's length at X1 once a frame).
  std::vector<uint32_t> point_neighbor_edges;  // one per point_neighbors slot
  std::vector<uint32_t> neighbor_edge_pairs;   // 2 per edge
  // True when every active point's triangle list (RigData::point_triangles) is exactly the
  // triangles that have it as a corner, ascending, each once (what the builder writes). The
  // fold limiter's worklist (docs/model.md §16) relies on it; without it, every pass scans
  // every active point and triangle (the same bits).
  bool point_triangles_exact = false;
  uint32_t edge_count() const { return uint32_t(edge_pairs.size() / 2); }
  uint32_t fine_edge_count() const { return uint32_t(fine_edge_pairs.size() / 2); }
  uint32_t neighbor_edge_count() const { return uint32_t(neighbor_edge_pairs.size() / 2); }
};

class Rig {
 public:
  Rig() = default;  // empty: no context accepts it
  Rig(Rig&&) noexcept = default;
  Rig& operator=(Rig&&) noexcept = default;
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  // The one writer: takes `data`, checks every table once (every index in range, every CSR
  // well formed, the active ranges exact, each stage job's own Validate over its full range),
  // derives the RigTables when the check passes, and gives the rig a fresh uid. Returns
  // tables_checked(); *out is replaced either way.
  static bool Build(RigData data, Rig* out);

  // Identity used by EvaluateContext to refuse a context sized for another rig: unique per
  // Build (never 0), kept by the rig it is moved to (a moved-from rig gets 0).
  uint64_t uid() const { return id_.uid; }
  // True when the tables passed the check Build made (EvaluateJob relies on it instead of
  // checking indices per frame).
  bool tables_checked() const { return id_.checked; }

  // What Build was given (copy it to make an edited rig).
  const RigData& data() const { return data_; }
  // What Build derived (empty when the check failed).
  const RigTables& tables() const { return tables_; }

  // Welded surface (see RigData).
  const std::vector<float3>& rest_points() const { return data_.rest_points; }
  const std::vector<uint32_t>& triangles() const { return data_.triangles; }
  const std::vector<uint32_t>& point_triangle_offsets() const { return data_.point_triangle_offsets; }
  const std::vector<uint32_t>& point_triangles() const { return data_.point_triangles; }
  const RigActiveRanges& active() const { return data_.active; }
  uint32_t active_point_count() const { return data_.active.points; }
  uint32_t normal_point_count() const { return data_.active.normal_points; }
  uint32_t active_triangle_count() const { return data_.active.triangles; }
  // The file's layout.
  const std::vector<uint32_t>& vertex_points() const { return data_.vertex_points; }
  const std::vector<uint32_t>& vertex_indices() const { return data_.vertex_indices; }
  const std::vector<float2>& vertex_uvs() const { return data_.vertex_uvs; }
  // Skin.
  const SkinLayers& layers() const { return data_.layers; }
  const std::vector<float>& point_thickness() const { return data_.point_thickness; }
  const std::vector<float>& rest_triangle_areas() const { return data_.rest_triangle_areas; }
  float min_area_ratio() const { return data_.min_area_ratio; }
  const std::vector<RigMuscleWrinkles>& muscle_wrinkles() const { return data_.muscle_wrinkles; }
  const RigCurveWrinkles& curve_wrinkles() const { return data_.curve_wrinkles; }
  // Muscles.
  const std::vector<std::string>& muscle_names() const { return data_.muscle_names; }
  const MuscleTable& muscles() const { return data_.muscles; }
  // The jaw (empty when the rig has none).
  const RigJaw& jaw() const { return data_.jaw; }
  // The eyeballs the lids slide on (empty when the rig has none).
  const RigEyes& eyes() const { return data_.eyes; }
  // Tension regions (empty when the rig has none).
  const RigTensionRegions& tension_regions() const { return data_.tension_regions; }
  uint32_t tension_region_count() const { return data_.tension_regions.region_count(); }
  // Fine-scale amplitude probes (empty when the rig has no fine-scale maps).
  const RigFineScale& fine_scale() const { return data_.fine_scale; }

  uint32_t point_count() const { return data_.point_count(); }
  uint32_t triangle_count() const { return data_.triangle_count(); }
  uint32_t vertex_count() const { return uint32_t(data_.vertex_points.size()); }
  uint32_t muscle_count() const { return data_.muscle_count(); }
  // Index of the muscle called `name`, or -1.
  int FindMuscle(std::string_view name) const;

  // Bytes this rig holds: sizeof(Rig) plus the capacity of every vector it owns, nested ones
  // included (a name counts its std::string object, not its characters).
  size_t ByteSize() const;

 private:
  // uid and check result; moving hands them over and leaves 0 / false behind.
  struct Identity {
    uint64_t uid = 0;
    bool checked = false;
    Identity() = default;
    Identity(Identity&& o) noexcept : uid(o.uid), checked(o.checked) { o = Identity(); }
    Identity& operator=(Identity&& o) noexcept {
      uid = o.uid;
      checked = o.checked;
      o.uid = 0;
      o.checked = false;
      return *this;
    }
  };
  RigData data_;
  RigTables tables_;
  Identity id_;
};

}  // namespace mimetic
