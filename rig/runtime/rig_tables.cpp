// rig/runtime/rig_tables.cpp: the one-time check and the derived tables of a rig (see
// rig_tables.h); Rig::Build runs both.
#include "rig/runtime/rig_tables.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rig/runtime/face_kernels.h"
#include "wrinkles/runtime/profiles.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

bool CheckRigData(const RigData& r) {
  const uint32_t points = r.point_count(), tris = r.triangle_count();
  for (uint32_t p : r.vertex_points)
    if (p >= points) return false;
  // The file's layout (read by RestMesh / PosedMesh and every exporter).
  if (r.vertex_indices.size() % 3 != 0) return false;
  for (uint32_t v : r.vertex_indices)
    if (v >= r.vertex_points.size()) return false;
  if (!r.vertex_uvs.empty() && r.vertex_uvs.size() != r.vertex_points.size()) return false;
  // Names, when given, are one per muscle / curve wrinkle; a wrinkled muscle exists.
  if (!r.curve_wrinkles.names.empty() &&
      r.curve_wrinkles.names.size() != r.curve_wrinkles.wrinkles.size())
    return false;
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles)
    if (w.muscle >= r.muscle_count() || !(w.gate >= 0.f && w.gate <= 1.f)) return false;
  for (uint32_t i : r.triangles)
    if (i >= points) return false;
  if (r.point_triangle_offsets.size() != size_t(points) + 1) return false;
  for (uint32_t p = 0; p < points; ++p)
    if (r.point_triangle_offsets[p] > r.point_triangle_offsets[p + 1]) return false;
  if (r.point_triangle_offsets[points] > r.point_triangles.size()) return false;
  for (uint32_t t : r.point_triangles)
    if (t >= tris) return false;
  // The ordering the per-frame ranges rely on (see RigActiveRanges).
  const uint32_t n_active = r.active.points, n_normal = r.active.normal_points;
  const uint32_t t_active = r.active.triangles;
  if (n_active > n_normal || n_normal > points || t_active > tris) return false;
  for (uint32_t p = n_active; p < points; ++p)  // muscles move active points only
    if (r.muscles.offsets.size() == size_t(points) + 1 &&
        r.muscles.offsets[p + 1] != r.muscles.offsets[p])
      return false;
  for (uint32_t t = 0; t < tris; ++t) {
    const uint32_t* c = &r.triangles[3 * t];
    const bool active = c[0] < n_active || c[1] < n_active || c[2] < n_active;
    if (active && t >= t_active) return false;  // its normal would be missed
  }
  for (uint32_t p = n_normal; p < points; ++p)  // static points see static triangles only
    for (uint32_t k = r.point_triangle_offsets[p]; k < r.point_triangle_offsets[p + 1]; ++k)
      if (r.point_triangles[k] < t_active) return false;
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles)
    for (uint32_t p : w.points)
      if (p >= n_active) return false;
  for (uint32_t p : r.curve_wrinkles.points)
    if (p >= n_active) return false;
  {  // the jaw: carried points ascending and active, weights in (0, 1], a unit axis, finite glide
    const RigJaw& j = r.jaw;
    if (j.weights.size() != j.points.size()) return false;
    for (size_t i = 0; i < j.points.size(); ++i) {
      if (j.points[i] >= n_active || (i > 0 && j.points[i] <= j.points[i - 1])) return false;
      if (!(j.weights[i] > 0.f && j.weights[i] <= 1.f)) return false;
    }
    if (!j.points.empty()) {
      const float len2 = Dot(j.axis, j.axis);
      if (!(std::fabs(len2 - 1.f) < 1e-4f) || !IsFinite(j.pivot) || !IsFinite(j.translation) || !(j.range > 0.f) ||
          !(j.range <= kMaxJawRange))
        return false;
    }
  }
  {  // the eyes: held points ascending and active, an eyeball each, positive finite radii,
     // weights in (0, 1], finite centres
    const RigEyes& e = r.eyes;
    const size_t n = e.points.size();
    if (e.eyes.size() != n || e.radii.size() != n || e.weights.size() != n) return false;
    for (const float3& c : e.centers)
      if (!IsFinite(c)) return false;
    for (size_t i = 0; i < n; ++i) {
      if (e.points[i] >= n_active || (i > 0 && e.points[i] <= e.points[i - 1])) return false;
      if (e.eyes[i] >= e.centers.size()) return false;
      if (!(e.radii[i] > 0.f && e.radii[i] < std::numeric_limits<float>::infinity())) return false;
      if (!(e.weights[i] > 0.f && e.weights[i] <= 1.f)) return false;
    }
  }
  {  // tension regions: named once each, a positive finite reference, a well-formed CSR of
     // ascending points with weights in (0, 1], and the rest areas their ratios need
    const RigTensionRegions& g = r.tension_regions;
    const size_t n = g.names.size();
    if (g.references.size() != n) return false;
    if (n == 0) {
      if (!g.offsets.empty() || !g.points.empty() || !g.weights.empty()) return false;
    } else {
      if (g.offsets.size() != n + 1 || g.offsets[0] != 0 || g.offsets[n] != g.points.size() ||
          g.weights.size() != g.points.size() || r.rest_triangle_areas.size() < tris)
        return false;
      for (size_t i = 0; i < n; ++i) {
        if (g.names[i].empty() || !(g.references[i] > 0.f) || !std::isfinite(g.references[i]))
          return false;
        for (size_t k = 0; k < i; ++k)
          if (g.names[k] == g.names[i]) return false;
        if (g.offsets[i] > g.offsets[i + 1]) return false;
        for (uint32_t e = g.offsets[i]; e < g.offsets[i + 1]; ++e) {
          if (g.points[e] >= points || (e > g.offsets[i] && g.points[e] <= g.points[e - 1]))
            return false;
          if (!(g.weights[e] > 0.f && g.weights[e] <= 1.f)) return false;
        }
      }
    }
  }
  {  // fine-scale probes: two per point of a leading range, each of its point, sides in
     // range (DirectionalShrinkageJob's own check), r in [0, 1]
    const RigFineScale& f = r.fine_scale;
    if (f.probes.size() % 2 != 0 || f.point_count() > points) return false;
    if (!f.empty() && !(f.rest_amplitude >= 0.f && f.rest_amplitude <= 1.f)) return false;
    for (size_t k = 0; k < f.probes.size(); ++k)
      if (f.probes[k].point != k / 2) return false;
    if (!f.empty()) {
      std::vector<float> s(f.probes.size());
      const DirectionalShrinkageJob job{.positions = r.rest_points,
                                        .probes = f.probes,
                                        .end = f.probes.size(),
                                        .out_shrinkage = s};
      if (!job.Validate()) return false;
      // Points past the probes never see a moving point (their s stays 0).
      if (f.point_count() < n_normal) return false;
    }
  }
  {
    const std::vector<float> activations(r.muscle_count(), 0.f);
    std::vector<float3> moved(size_t(points) + 1);  // EvaluateContext's padded point buffer
    const MuscleDeformJob muscles{.table = &r.muscles,
                                  .activations = activations,
                                  .rest_points = r.rest_points,
                                  .out_points = moved,
                                  .begin = 0,
                                  .end = points};
    if (!muscles.Validate()) return false;
  }
  for (const MuscleInfluence& e : r.muscles.entries)
    if (e.muscle >= r.muscle_count()) return false;
  // The muscle CSR is non-decreasing (MuscleDeformJob::Validate checks its ends only).
  for (size_t p = 0; p + 1 < r.muscles.offsets.size(); ++p)
    if (r.muscles.offsets[p] > r.muscles.offsets[p + 1]) return false;
  const bool skin = r.layers.thickness || r.layers.muscle_wrinkles || r.layers.curve_wrinkles;
  if (!skin) return true;
  if (r.rest_triangle_areas.size() < tris || r.point_thickness.size() < points) return false;
  // The stage jobs' own checks over full ranges (scratch outputs; positions and normals need
  // only the point count).
  const span<const float3> any_points = r.rest_points;
  std::vector<float3> scratch_points(points);
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles) {
    std::vector<float> eps(w.row_count());
    const EdgeCompressionJob compression{.positions = any_points,
                                         .points = w.points,
                                         .offsets = w.edge_offsets,
                                         .neighbors = w.edge_neighbors,
                                         .rest_lengths = w.edge_rest_lengths,
                                         .weights = w.edge_weights,
                                         .end = w.row_count(),
                                         .out_compression = eps};
    const MuscleWrinkleJob wrinkle{.normals = any_points,
                                   .points = w.points,
                                   .phase = w.phase,
                                   .attenuation = w.attenuation,
                                   .compression = eps,
                                   .half_cycle = w.half_cycle,
                                   .furrow_depth = w.furrow_depth,
                                   .shape = w.shape,
                                   .end = w.row_count(),
                                   .positions = scratch_points,
                                   .out_amplitudes = {},
                                   .profile = w.profile};
    if (!compression.Validate() || !wrinkle.Validate()) return false;
  }
  const RigCurveWrinkles& c = r.curve_wrinkles;
  if (!c.entries.empty() || c.row_count() > 0) {
    std::vector<float> s(c.probes.size()), ratios(points, 1.f);
    const DirectionalShrinkageJob shrinkage{.positions = any_points,
                                            .probes = c.probes,
                                            .end = c.probes.size(),
                                            .out_shrinkage = s};
    const CurveWrinkleJob curves{.normals = any_points,
                                 .wrinkles = c.wrinkles,
                                 .points = c.points,
                                 .offsets = c.offsets,
                                 .entries = c.entries,
                                 .entry_shrinkage = s,
                                 .area_ratios = ratios,
                                 .end = c.row_count(),
                                 .positions = scratch_points,
                                 .out_amplitudes = {}};
    if (!shrinkage.Validate() || !curves.Validate() || c.probes.size() != c.entries.size())
      return false;
  }
  return true;
}

namespace {

// Numbers the edges that `each_lookup` looks up, in first-seen order: each_lookup(fn) calls
// fn(a, b, id) once per lookup of the edge of points a and b (either order, both below
// point_count), in the same order every time; the edge's id is written to *id and each new
// edge's two points (smaller first) are appended to `pairs`. It is called twice: first to count
// the lookups of each smaller point (ids not written), then to number them (so the lookups
// are never stored: on the sample head 1.76 M of them, 21 MB as keys and ids). The edges whose
// smaller point is a are kept in bucket a, which has one slot per lookup of a (so it is at least
// as large as a's count of edges; on the sample head about five lookups per edge): a small
// open-addressing table inside the bucket, keyed by b (each slot the other point and the id side
// by side), so a lookup reads one or two slots of one point's few instead of scanning them, and
// the buckets are visited in nearly ascending order (a hash over all edges missed the cache on
// nearly every probe).
template <class EachLookup>
void AssignEdgeIds(uint32_t point_count, EachLookup each_lookup, std::vector<uint32_t>* pairs) {
  std::vector<uint32_t> start(size_t(point_count) + 1, 0u);
  uint32_t* first = start.data();
  each_lookup([first](uint32_t a, uint32_t b, uint32_t*) { ++first[size_t(a < b ? a : b) + 1]; });
  for (uint32_t p = 0; p < point_count; ++p) start[p + 1] += start[p];
  struct Slot {
    uint32_t b, id;
  };
  constexpr uint32_t kEmpty = ~0u;  // no point has this index (b < point_count)
  std::vector<Slot> slots(start[point_count], Slot{kEmpty, 0u});
  Slot* slot = slots.data();
  uint32_t edges = uint32_t(pairs->size() / 2);
  each_lookup([&, first, slot](uint32_t a, uint32_t b, uint32_t* id) {
    if (a > b) std::swap(a, b);
    Slot* bucket = slot + first[a];
    const uint32_t size = first[a + 1] - first[a];  // >= 1: this lookup is counted
    uint32_t k = uint32_t((uint64_t(b * 0x9E3779B1u) * size) >> 32);  // in [0, size)
    while (bucket[k].b != b && bucket[k].b != kEmpty) k = k + 1 == size ? 0 : k + 1;
    if (bucket[k].b == kEmpty) {  // a free slot exists: a has at most `size` edges
      bucket[k] = {b, edges++};
      pairs->push_back(a);
      pairs->push_back(b);
    }
    *id = bucket[k].id;
  });
}

// The lookups of shrinkage probes for AssignEdgeIds: each probe's sides' v1v2 and v1v3, into
// slots[4 k + 2 s] and slots[4 k + 2 s + 1].
template <class Edge>
void ProbeLookups(const std::vector<ShrinkageProbe>& probes, uint32_t* slots, Edge& edge) {
  for (size_t k = 0; k < probes.size(); ++k) {
    const ShrinkageProbe& probe = probes[k];
    for (uint32_t s = 0; s < probe.side_count; ++s) {
      edge(probe.point, probe.sides[s].v2, &slots[4 * k + 2 * s]);
      edge(probe.point, probe.sides[s].v3, &slots[4 * k + 2 * s + 1]);
    }
  }
}

// The fused strain and displacement tables (see RigTables): edges read by the compression rows
// and the shrinkage probes, each once; per-row coefficients; per-point row lists.
void BuildStrainTables(const RigData& r, RigTables* out) {
  RigTables& t = *out;
  t.edge_pairs.clear();
  // Muscle-wrinkle rows, point-major: a point's rows are contiguous (in rig order among
  // themselves, so its sum adds them in the order MuscleWrinkleJob would), and so are their
  // entries.
  const uint32_t active = r.active.points;
  struct RowRef {
    const RigMuscleWrinkles* table;
    uint32_t index;
  };
  // Each point's rows, as CSR in rig order (a count, a prefix sum, a fill).
  std::vector<uint32_t> row_start(size_t(active) + 1, 0u);
  size_t row_total = 0, entry_total = 0;
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles) {
    for (uint32_t i = 0; i < w.row_count(); ++i) ++row_start[size_t(w.points[i]) + 1];
    row_total += w.row_count();
    entry_total += w.edge_neighbors.size();
  }
  for (uint32_t p = 0; p < active; ++p) row_start[p + 1] += row_start[p];
  std::vector<RowRef> row_refs(row_total);
  {
    std::vector<uint32_t> fill(row_start.begin(), row_start.end() - 1);
    for (const RigMuscleWrinkles& w : r.muscle_wrinkles)
      for (uint32_t i = 0; i < w.row_count(); ++i) row_refs[fill[w.points[i]]++] = {&w, i};
  }
  const RigCurveWrinkles& c = r.curve_wrinkles;
  t.row_offsets.resize(row_total + 1);
  t.entry_edges.resize(entry_total);  // by AssignEdgeIds below
  t.entry_rest.resize(entry_total);
  t.entry_coeffs.resize(entry_total);
  t.row_profiles.resize(row_total);
  t.row_muscles.resize(row_total);
  t.point_row_offsets.resize(size_t(active) + 1);
  t.row_offsets[0] = 0;
  t.point_row_offsets[0] = 0;
  size_t row = 0, entry = 0;
  for (uint32_t p = 0; p < active; ++p) {
    for (uint32_t j = row_start[p]; j < row_start[p + 1]; ++j, ++row) {
      const RowRef& ref = row_refs[j];
      const RigMuscleWrinkles& w = *ref.table;
      const uint32_t i = ref.index;
      t.row_profiles[row] = w.profile.empty()
                                ? MuscleWrinkleProfile(w.phase[i], w.half_cycle, w.furrow_depth,
                                                       w.shape, w.attenuation[i])
                                : w.profile[i];
      t.row_muscles[row] = w.muscle;
      float weight_sum = 0.f;
      for (uint32_t k = w.edge_offsets[i]; k < w.edge_offsets[i + 1]; ++k)
        weight_sum += w.edge_weights[k];
      for (uint32_t k = w.edge_offsets[i]; k < w.edge_offsets[i + 1]; ++k, ++entry) {
        const float rest = w.edge_rest_lengths[k];
        t.entry_rest[entry] = rest;
        // 001 eq. 9-10: eps = sum_j w_j (L_j - l_j) / L_j / sum_j w_j, as sum_j c_j (L_j - l_j)
        // (no division per frame; L_j - l_j is exactly 0 at rest, so is eps).
        t.entry_coeffs[entry] =
            rest > 0.f && weight_sum > 0.f ? w.edge_weights[k] / (rest * weight_sum) : 0.f;
      }
      t.row_offsets[row + 1] = uint32_t(entry);
    }
    t.point_row_offsets[p + 1] = uint32_t(row);
  }
  // Edge ids in first-seen order (AssignEdgeIds): each entry's edge (its point and its
  // neighbour, the rows point-major as above), then each curve-wrinkle probe's sides, then the
  // fine-scale probes' sides (docs/model.md §23, 4 per probe: sides' v1v2, v1v3). The strain's
  // lookups come first, so its edges are ids [0, E) whatever the fine-scale probes add; the
  // edges only those probes read follow as [E, E + F) (RigTables::fine_edge_pairs), and the
  // probes' edges the strain reads too keep their strain ids (one length a frame for both).
  t.probe_edges.assign(4 * c.probes.size(), 0u);
  const RigFineScale& f = r.fine_scale;
  std::vector<uint32_t> probe_slots(4 * f.probes.size(), 0u);
  std::vector<uint32_t> all_pairs;
  size_t strain_pairs = 0;  // 2 E, counted as the strain's lookups go by (the second walk)
  AssignEdgeIds(r.point_count(), [&](auto&& edge) {
    uint32_t* entry_edge = t.entry_edges.data();
    for (const RowRef& ref : row_refs) {
      const RigMuscleWrinkles& w = *ref.table;
      const uint32_t i = ref.index, p = w.points[i];
      for (uint32_t k = w.edge_offsets[i]; k < w.edge_offsets[i + 1]; ++k)
        edge(p, w.edge_neighbors[k], entry_edge++);
    }
    ProbeLookups(c.probes, t.probe_edges.data(), edge);
    strain_pairs = all_pairs.size();
    ProbeLookups(f.probes, probe_slots.data(), edge);
  }, &all_pairs);
  t.edge_pairs.assign(all_pairs.begin(), all_pairs.begin() + strain_pairs);
  t.fine_edge_pairs.assign(all_pairs.begin() + strain_pairs, all_pairs.end());
  // The blocked layout (RigTables::fine_probe_edges): what SideShrinkageFromLengths does with
  // a rest length that is not positive (l = L = 1) is a read of the length-1 slot.
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  const uint32_t one = t.edge_count() + t.fine_edge_count();
  const size_t blocks = (f.probes.size() + B - 1) / B;
  t.fine_probe_edges.assign(blocks * 4 * B, one);
  t.fine_probe_params.assign(blocks * 7 * B, 0.f);
  for (size_t i = 0; i < blocks * B; ++i) {
    uint32_t* e = &t.fine_probe_edges[(i / B) * 4 * B + i % B];
    float* q = &t.fine_probe_params[(i / B) * 7 * B + i % B];
    const ShrinkageProbe* probe = i < f.probes.size() ? &f.probes[i] : nullptr;
    for (uint32_t s = 0; s < 2; ++s) {
      q[(3 * s + 1) * B] = q[(3 * s + 2) * B] = 1.f;
      if (!probe || s >= probe->side_count) continue;
      const ShrinkageSide& side = probe->sides[s];
      q[3 * s * B] = side.beta;
      if (side.rest_length2 > 0.f) {
        q[(3 * s + 1) * B] = side.rest_length2;
        e[2 * s * B] = probe_slots[4 * i + 2 * s];
      }
      if (side.rest_length3 > 0.f) {
        q[(3 * s + 2) * B] = side.rest_length3;
        e[(2 * s + 1) * B] = probe_slots[4 * i + 2 * s + 1];
      }
    }
    q[6 * B] = probe && probe->side_count == 2 ? 0.5f : 1.f;
  }
  // Each point's curve-wrinkle rows, as CSR in row order.
  t.point_curve_offsets.assign(size_t(active) + 1, 0u);
  for (uint32_t i = 0; i < c.row_count(); ++i) ++t.point_curve_offsets[size_t(c.points[i]) + 1];
  for (uint32_t p = 0; p < active; ++p) t.point_curve_offsets[p + 1] += t.point_curve_offsets[p];
  t.point_curve_rows.assign(c.row_count(), 0u);
  {
    std::vector<uint32_t> fill(t.point_curve_offsets.begin(), t.point_curve_offsets.end() - 1);
    for (uint32_t i = 0; i < c.row_count(); ++i) t.point_curve_rows[fill[c.points[i]]++] = i;
  }
  t.wrinkle_points.clear();
  for (uint32_t p = 0; p < active; ++p)
    if (row_start[p + 1] > row_start[p] ||
        t.point_curve_offsets[p + 1] > t.point_curve_offsets[p])
      t.wrinkle_points.push_back(p);
}

// RigTables::point_triangles_exact, the count half: each active point lists exactly as many
// triangles as have it as a corner (a triangle counted once per point however often the point
// repeats among its corners). The other half (each listed triangle has the point as a corner,
// the list ascending: then, with the count, it is exactly those triangles, each once) is
// checked in BuildRigTables' one-ring loop, which reads those corners anyway.
bool PointTriangleCountsExact(const RigData& r) {
  const uint32_t n_active = r.active.points;
  const uint32_t* off = r.point_triangle_offsets.data();
  std::vector<uint32_t> incident(n_active, 0);
  for (uint32_t t = 0; t < r.triangle_count(); ++t) {
    const uint32_t* c = &r.triangles[3 * size_t(t)];
    for (int j = 0; j < 3; ++j)
      if (c[j] < n_active && (j < 1 || c[j] != c[0]) && (j < 2 || c[j] != c[1])) ++incident[c[j]];
  }
  for (uint32_t p = 0; p < n_active; ++p)
    if (off[p + 1] - off[p] != incident[p]) return false;
  return true;
}

}  // namespace

void BuildRigTables(const RigData& r, RigTables* out) {
  RigTables& t = *out;
  // Rest face and point normals with the kernels (and the padded point buffer) EvaluateJob
  // uses, so that a point that never changes normal reads the bits a gather would give.
  const uint32_t points = r.point_count(), tris = r.triangle_count();
  static_assert(kPointPadFloats <= 3, "pad the rest points by more than one float3");
  std::vector<float3> padded(size_t(points) + 1, float3{});
  std::copy(r.rest_points.begin(), r.rest_points.end(), padded.begin());
  t.rest_faces.assign(tris, float4{});
  FaceNormals4(padded.data(), r.triangles.data(), 0, tris, nullptr, t.rest_faces.data());
  t.rest_point_normals.assign(points, float3{});
  for (uint32_t p = 0; p < points; ++p)
    t.rest_point_normals[p] = UnitNormal(GatherFaces4(r.point_triangle_offsets.data(),
                                                      r.point_triangles.data(),
                                                      t.rest_faces.data(), p));
  BuildStrainTables(r, out);
  // The one-ring of each active point, each neighbour once, ascending.
  // (A stamp per point keeps each neighbour once; the few left are insertion-sorted.)
  t.point_neighbor_offsets.assign(size_t(r.active.points) + 1, 0);
  t.point_neighbors.clear();
  t.point_neighbors.reserve(size_t(r.active.points) * 7);
  std::vector<uint32_t> stamp(points, ~0u);
  bool lists_exact = true;  // every listed triangle has p as a corner, the list ascending
  for (uint32_t p = 0; p < r.active.points; ++p) {
    const size_t first = t.point_neighbors.size();
    stamp[p] = p;
    for (uint32_t k = r.point_triangle_offsets[p]; k < r.point_triangle_offsets[p + 1]; ++k) {
      const uint32_t* corner = &r.triangles[3 * size_t(r.point_triangles[k])];
      lists_exact = lists_exact && (corner[0] == p || corner[1] == p || corner[2] == p) &&
                    (k == r.point_triangle_offsets[p] ||
                     r.point_triangles[k] > r.point_triangles[k - 1]);
      for (int j = 0; j < 3; ++j) {
        const uint32_t q = corner[j];
        if (stamp[q] == p) continue;
        stamp[q] = p;
        // Insert q into the sorted tail [first, end): its place is the count of smaller
        // neighbours (counted without a data-dependent branch), the larger ones shift up.
        t.point_neighbors.push_back(q);
        uint32_t* ring = t.point_neighbors.data() + first;
        const size_t n = t.point_neighbors.size() - 1 - first;
        size_t at = 0;
        for (size_t i = 0; i < n; ++i) at += ring[i] < q;
        for (size_t i = n; i > at; --i) ring[i] = ring[i - 1];
        ring[at] = q;
      }
    }
    t.point_neighbor_offsets[p + 1] = uint32_t(t.point_neighbors.size());
  }
  // The edges of those one-rings, each once (docs/model.md §16: the limiter's edge lengths
  // at X1, measured once per edge instead of once from each end), numbered as met in point
  // order: p's slot for q names the edge p-q, new unless q is an active point before p, whose
  // ascending list then holds p.
  t.neighbor_edge_pairs.clear();
  t.point_neighbor_edges.assign(t.point_neighbors.size(), 0);
  for (uint32_t p = 0; p < r.active.points; ++p) {
    for (uint32_t k = t.point_neighbor_offsets[p]; k < t.point_neighbor_offsets[p + 1]; ++k) {
      const uint32_t q = t.point_neighbors[k];
      if (q < p) {  // q is active (below p) and met p first: find p in q's list
        const uint32_t* begin = t.point_neighbors.data() + t.point_neighbor_offsets[q];
        const uint32_t* end = t.point_neighbors.data() + t.point_neighbor_offsets[q + 1];
        const uint32_t* at = std::lower_bound(begin, end, p);
        if (at != end && *at == p) {  // (always, where the triangle lists are a mesh's)
          t.point_neighbor_edges[k] = t.point_neighbor_edges[size_t(at - t.point_neighbors.data())];
          continue;
        }
      }
      t.point_neighbor_edges[k] = uint32_t(t.neighbor_edge_pairs.size() / 2);
      t.neighbor_edge_pairs.push_back(p);
      t.neighbor_edge_pairs.push_back(q);
    }
  }
  t.point_triangles_exact = lists_exact && PointTriangleCountsExact(r);
  // Give back any slack (the lists built by push_back; a table rebuilt in place keeps its old
  // capacity).
  for (std::vector<uint32_t>* v : {&t.edge_pairs, &t.row_offsets, &t.entry_edges, &t.probe_edges,
                                   &t.point_row_offsets, &t.point_curve_offsets,
                                   &t.point_curve_rows, &t.wrinkle_points, &t.point_neighbors,
                                   &t.neighbor_edge_pairs,
                                   &t.row_muscles})
    v->shrink_to_fit();
  for (std::vector<float>* v : {&t.entry_rest, &t.entry_coeffs, &t.row_profiles})
    v->shrink_to_fit();
}

}  // namespace mimetic
