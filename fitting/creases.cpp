// fitting/creases.cpp: MeasureCreases and CreaseMeter.
#include "fitting/creases.h"

#include <algorithm>
#include <cmath>

#include "geometry/normals.h"

namespace mimetic {
namespace {

// The angle between the two face normals of an interior edge, degrees.
double Dihedral(const std::vector<float3>& p, const uint32_t* t0, const uint32_t* t1) {
  double n0[3], n1[3];
  TriangleCross(p[t0[0]], p[t0[1]], p[t0[2]], n0);
  TriangleCross(p[t1[0]], p[t1[1]], p[t1[2]], n1);
  const double l0 = std::sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
  const double l1 = std::sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
  if (!(l0 > 0.0) || !(l1 > 0.0)) return 0.0;
  const double c = (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2]) / (l0 * l1);
  return std::acos(std::clamp(c, -1.0, 1.0)) * (180.0 / 3.14159265358979323846);
}

}  // namespace

CreaseMeter::CreaseMeter(span<const float3> rest, span<const uint32_t> triangles, int rings,
                         double min_shape)
    : rest_(rest.begin(), rest.end()),
      tris_(triangles.begin(), triangles.begin() + std::ptrdiff_t(triangles.size() / 3 * 3)),
      rings_(std::max(0, rings)) {
  BuildEdgeTable(tris_, &edges_);
  neighbours_ = BuildPointNeighbors(tris_, rest_.size());
  rest_angle_.assign(edges_.edge_count(), 0.f);
  auto shape = [&](const uint32_t* t) { return TriangleShape(rest_[t[0]], rest_[t[1]], rest_[t[2]]); };
  for (size_t e = 0; e < edges_.edge_count(); ++e)
    if (edges_.use_count(e) == 2) {
      const uint32_t* t0 = &tris_[3 * (edges_.corners[edges_.start[e]] / 3)];
      const uint32_t* t1 = &tris_[3 * (edges_.corners[edges_.start[e] + 1] / 3)];
      const bool sliver = shape(t0) < min_shape || shape(t1) < min_shape;
      rest_angle_[e] = sliver ? std::nanf("") : float(Dihedral(rest_, t0, t1));
      sliver_edges_ += sliver ? 1u : 0u;
    }
}

double CreaseMeter::Measure(span<const float3> displacement, uint32_t* band_edges,
                            float3* worst_at) const {
  const size_t np = rest_.size();
  std::vector<float3> posed = rest_;
  std::vector<uint8_t> moved(np, 0), band(np, 0), grow;
  for (size_t p = 0; p < np && p < displacement.size(); ++p) {
    const float3 d = displacement[p];
    if (d.x != 0.f || d.y != 0.f || d.z != 0.f) {
      posed[p] += d;
      moved[p] = 1;
    }
  }
  // The boundary: moved points next to unmoved ones, and those unmoved neighbours.
  for (size_t p = 0; p < np; ++p)
    for (uint32_t k = neighbours_.offsets[p]; k < neighbours_.offsets[p + 1]; ++k)
      if (moved[p] != moved[neighbours_.items[k]]) band[p] = 1;
  for (int r = 0; r < rings_; ++r) {
    grow = band;
    for (size_t p = 0; p < np; ++p)
      if (band[p])
        for (uint32_t k = neighbours_.offsets[p]; k < neighbours_.offsets[p + 1]; ++k)
          grow[neighbours_.items[k]] = 1;
    band.swap(grow);
  }
  double worst = 0.0;
  uint32_t counted = 0;
  float3 at = np ? rest_[0] : float3{0.f, 0.f, 0.f};
  for (size_t e = 0; e < edges_.edge_count(); ++e) {
    if (edges_.use_count(e) != 2 || std::isnan(rest_angle_[e])) continue;
    const uint32_t a = EdgeKeyLow(edges_.keys[e]), b = EdgeKeyHigh(edges_.keys[e]);
    if (!band[a] || !band[b]) continue;
    ++counted;
    const double angle = Dihedral(posed, &tris_[3 * (edges_.corners[edges_.start[e]] / 3)],
                                  &tris_[3 * (edges_.corners[edges_.start[e] + 1] / 3)]);
    const double change = std::fabs(angle - double(rest_angle_[e]));
    if (change > worst) {
      worst = change;
      at = (rest_[a] + rest_[b]) * 0.5f;
    }
  }
  if (band_edges) *band_edges = counted;
  if (worst_at) *worst_at = at;
  return worst;
}

bool BuildRigWithFalloff(RigSpec spec, const MeshData& mesh, MuscleFalloff falloff, Rig* out,
                         Diagnostics* diag) {
  for (MuscleSpec& m : spec.muscles) m.falloff = falloff;
  return BuildRig(spec, mesh, {}, out, diag);
}

CreaseReport MeasureCreases(const Rig& rig, int rings, double min_shape) {
  CreaseReport out;
  const uint32_t np = rig.point_count(), nm = rig.muscle_count();
  out.muscle_degrees.assign(nm, 0.f);
  out.band_edges.assign(nm, 0);
  out.worst_at.assign(nm, float3{0.f, 0.f, 0.f});
  const CreaseMeter meter(rig.rest_points(), rig.triangles(), rings, min_shape);
  out.sliver_edges = meter.sliver_edges();
  const MuscleTable& table = rig.muscles();
  std::vector<float3> displacement(np);
  for (uint32_t m = 0; m < nm; ++m) {
    std::fill(displacement.begin(), displacement.end(), float3{0.f, 0.f, 0.f});
    for (uint32_t p = 0; p < np && p + 1 < table.offsets.size(); ++p)
      for (uint32_t k = table.offsets[p]; k < table.offsets[p + 1]; ++k)
        if (table.entries[k].muscle == m) displacement[p] += table.entries[k].displacement;
    out.muscle_degrees[m] = float(meter.Measure(displacement, &out.band_edges[m], &out.worst_at[m]));
    if (out.muscle_degrees[m] > out.max_degrees) {
      out.max_degrees = out.muscle_degrees[m];
      out.worst_muscle = m;
    }
  }
  return out;
}

}  // namespace mimetic
