// fitting/creases.cpp: MeasureCreases.
#include "fitting/creases.h"

#include <algorithm>
#include <cmath>

#include "geometry/normals.h"
#include "geometry/topology.h"

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

CreaseReport MeasureCreases(const Rig& rig, int rings) {
  CreaseReport out;
  const uint32_t np = rig.point_count(), nm = rig.muscle_count();
  const std::vector<uint32_t>& tris = rig.triangles();
  out.muscle_degrees.assign(nm, 0.f);
  out.band_edges.assign(nm, 0);
  EdgeTable edges;
  BuildEdgeTable(tris, &edges);
  const CsrTable neighbours = BuildPointNeighbors(tris, np);
  std::vector<float> rest_angle(edges.edge_count(), 0.f);
  for (size_t e = 0; e < edges.edge_count(); ++e)
    if (edges.use_count(e) == 2)
      rest_angle[e] = float(Dihedral(rig.rest_points(), &tris[3 * (edges.corners[edges.start[e]] / 3)],
                                     &tris[3 * (edges.corners[edges.start[e] + 1] / 3)]));
  const MuscleTable& table = rig.muscles();
  std::vector<float3> posed;
  std::vector<uint8_t> moved(np), band(np), grow(np);
  for (uint32_t m = 0; m < nm; ++m) {
    posed = rig.rest_points();
    std::fill(moved.begin(), moved.end(), 0);
    for (uint32_t p = 0; p < np && p + 1 < table.offsets.size(); ++p)
      for (uint32_t k = table.offsets[p]; k < table.offsets[p + 1]; ++k)
        if (table.entries[k].muscle == m) {
          posed[p] += table.entries[k].displacement;
          moved[p] = 1;
        }
    // The boundary: moved points next to unmoved ones, and those unmoved neighbours.
    std::fill(band.begin(), band.end(), 0);
    for (uint32_t p = 0; p < np; ++p)
      for (uint32_t k = neighbours.offsets[p]; k < neighbours.offsets[p + 1]; ++k)
        if (moved[p] != moved[neighbours.items[k]]) band[p] = 1;
    for (int r = 0; r < rings; ++r) {
      grow = band;
      for (uint32_t p = 0; p < np; ++p)
        if (band[p])
          for (uint32_t k = neighbours.offsets[p]; k < neighbours.offsets[p + 1]; ++k)
            grow[neighbours.items[k]] = 1;
      band.swap(grow);
    }
    double worst = 0.0;
    for (size_t e = 0; e < edges.edge_count(); ++e) {
      if (edges.use_count(e) != 2) continue;
      const uint32_t a = EdgeKeyLow(edges.keys[e]), b = EdgeKeyHigh(edges.keys[e]);
      if (!band[a] || !band[b]) continue;
      ++out.band_edges[m];
      const double angle = Dihedral(posed, &tris[3 * (edges.corners[edges.start[e]] / 3)],
                                    &tris[3 * (edges.corners[edges.start[e] + 1] / 3)]);
      worst = std::max(worst, std::fabs(angle - double(rest_angle[e])));
    }
    out.muscle_degrees[m] = float(worst);
    if (out.muscle_degrees[m] > out.max_degrees) {
      out.max_degrees = out.muscle_degrees[m];
      out.worst_muscle = m;
    }
  }
  return out;
}

}  // namespace mimetic
