#include "muscles/offline/muscle_builder.h"

#include <algorithm>
#include <cmath>

#include "muscles/offline/waters.h"

namespace mimetic {
namespace {

// A sphere that holds every point a muscle can move (docs/model.md §2-3): a linear muscle moves
// nothing farther than Rf from v1; a sheet muscle nothing outside 0 <= l <= Ls along the central
// fiber from mAc and h <= Ws / 2 across it, a box inside the sphere around its middle. `all`:
// no usable bound (a degenerate or non-finite spec): test every point.
struct Reach {
  double x = 0, y = 0, z = 0, r = 0;
  bool all = true;
};

Reach ReachOf(const MuscleSpec& m) {
  Reach b;
  if (m.type == MuscleType::kLinear) {
    b = {m.linear.attachment.x, m.linear.attachment.y, m.linear.attachment.z,
         m.linear.falloff_end, false};
  } else {
    const SheetMuscleSpec& s = m.sheet;
    const double ax = 0.5 * (double(s.attachment[0].x) + s.attachment[1].x);
    const double ay = 0.5 * (double(s.attachment[0].y) + s.attachment[1].y);
    const double az = 0.5 * (double(s.attachment[0].z) + s.attachment[1].z);
    const double fx = 0.5 * (double(s.insertion[0].x) + s.insertion[1].x) - ax;
    const double fy = 0.5 * (double(s.insertion[0].y) + s.insertion[1].y) - ay;
    const double fz = 0.5 * (double(s.insertion[0].z) + s.insertion[1].z) - az;
    const double len = std::sqrt(fx * fx + fy * fy + fz * fz);
    if (!(len > 0.0)) return {};
    const double half = 0.5 * double(s.length) / len;
    b = {ax + fx * half, ay + fy * half, az + fz * half,
         std::hypot(0.5 * double(s.length), 0.5 * double(s.width)), false};
  }
  // A margin for the rounding of the formulas' own arithmetic (they compare in double).
  b.r = b.r * (1.0 + 1e-6) + 1e-9;
  if (!std::isfinite(b.x) || !std::isfinite(b.y) || !std::isfinite(b.z) || !std::isfinite(b.r))
    return {};
  return b;
}

bool Finite(float3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

// Linear in #points + #muscles + the work inside each muscle's reach: the points are bucketed
// in a uniform grid (about one point per cell), each muscle visits only the cells its reach
// overlaps, and the influences, found muscle by muscle, are put in point-major order by a
// stable counting sort (so a point's muscles stay in ascending order). The result is the same,
// entry for entry, as evaluating every muscle at every point.
float3 ApplyMuscleMotion(float3 d, float3 normal, MuscleMotion motion) {
  if (motion == MuscleMotion::kChord) return d;
  return d - Dot(d, normal) * normal;
}

namespace {

// Where muscle m's motion takes its normals: a span over every point, the averaged field of a
// radius (asked point by point, so only the points the muscle reaches are summed), or nothing
// (it moves along the chord).
struct NormalsOf {
  span<const float3> points;
  NormalField* field = nullptr;
  float radius = 0.f;
};

MuscleTable BuildTable(span<const MuscleSpec> muscles, span<const float3> rest_points,
                       const std::vector<NormalsOf>& normals) {
  MuscleTable table;
  const size_t np = rest_points.size();
  table.muscle_count = uint32_t(muscles.size());
  table.offsets.assign(np + 1, 0u);
  if (np == 0 || muscles.empty()) return table;

  // The grid over the finite points (a non-finite point is moved by no muscle).
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  size_t finite = 0;
  for (const float3& p : rest_points) {
    if (!Finite(p)) continue;
    ++finite;
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
  }
  if (finite == 0) return table;
  double extent = 0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, hi[k] - lo[k]);
  const double cell = extent > 0 ? extent / std::max(1.0, std::cbrt(double(finite))) : 1.0;
  int64_t dim[3];
  for (int k = 0; k < 3; ++k)
    dim[k] = std::clamp<int64_t>(int64_t((hi[k] - lo[k]) / cell) + 1, 1, 1024);
  auto cell_of = [&](int k, double v) {
    return std::clamp<int64_t>(int64_t(std::floor((v - lo[k]) / cell)), 0, dim[k] - 1);
  };
  const size_t cells = size_t(dim[0] * dim[1] * dim[2]);
  std::vector<uint32_t> cell_start(cells + 1, 0u), cell_points(finite);
  std::vector<uint32_t> point_cell(np, UINT32_MAX);
  for (size_t p = 0; p < np; ++p) {
    const float3 q = rest_points[p];
    if (!Finite(q)) continue;
    point_cell[p] = uint32_t((cell_of(2, q.z) * dim[1] + cell_of(1, q.y)) * dim[0] + cell_of(0, q.x));
    ++cell_start[point_cell[p] + 1];
  }
  for (size_t c = 0; c < cells; ++c) cell_start[c + 1] += cell_start[c];
  {
    std::vector<uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
    for (size_t p = 0; p < np; ++p)
      if (point_cell[p] != UINT32_MAX) cell_points[fill[point_cell[p]]++] = uint32_t(p);
  }

  // Influences muscle by muscle, then point-major.
  struct Found {
    uint32_t point;
    MuscleInfluence influence;
  };
  std::vector<Found> found;
  auto visit = [&](uint32_t m, uint32_t p) {
    float3 d = MuscleDisplacement(muscles[m], rest_points[p], muscles[m].strength);
    if (d.x == 0.f && d.y == 0.f && d.z == 0.f) return;  // the ball's corners past the fall-off
    if (normals[m].field)
      d = ApplyMuscleMotion(d, normals[m].field->At(normals[m].radius, p), muscles[m].motion);
    else if (normals[m].points.size() == rest_points.size())
      d = ApplyMuscleMotion(d, normals[m].points[p], muscles[m].motion);
    if (d.x != 0.f || d.y != 0.f || d.z != 0.f) found.push_back({p, {m, d}});  // a pull along the normal
  };
  for (uint32_t m = 0; m < muscles.size(); ++m) {
    const Reach b = ReachOf(muscles[m]);
    if (b.all) {
      for (uint32_t p = 0; p < np; ++p)
        if (point_cell[p] != UINT32_MAX) visit(m, p);
      continue;
    }
    const double c[3] = {b.x, b.y, b.z};
    int64_t from[3], to[3];
    bool empty = false;
    for (int k = 0; k < 3; ++k) {
      if (c[k] + b.r < lo[k] || c[k] - b.r > hi[k]) empty = true;
      from[k] = cell_of(k, c[k] - b.r);
      to[k] = cell_of(k, c[k] + b.r);
    }
    if (empty) continue;
    const size_t first = found.size();
    for (int64_t z = from[2]; z <= to[2]; ++z)
      for (int64_t y = from[1]; y <= to[1]; ++y)
        for (int64_t x = from[0]; x <= to[0]; ++x) {
          const size_t id = size_t((z * dim[1] + y) * dim[0] + x);
          for (uint32_t k = cell_start[id]; k < cell_start[id + 1]; ++k) {
            const uint32_t p = cell_points[k];
            const float3 q = rest_points[p];
            const double dx = q.x - b.x, dy = q.y - b.y, dz = q.z - b.z;
            if (dx * dx + dy * dy + dz * dz <= b.r * b.r) visit(m, p);
          }
        }
    // One muscle's points in ascending order (cells are visited out of point order).
    std::sort(found.begin() + first, found.end(),
              [](const Found& a, const Found& b) { return a.point < b.point; });
  }
  for (const Found& f : found) ++table.offsets[f.point + 1];
  for (size_t p = 0; p < np; ++p) table.offsets[p + 1] += table.offsets[p];
  table.entries.resize(found.size());
  std::vector<uint32_t> fill(table.offsets.begin(), table.offsets.end() - 1);
  for (const Found& f : found) table.entries[fill[f.point]++] = f.influence;
  return table;
}

}  // namespace

MuscleTable BuildMuscleTable(span<const MuscleSpec> muscles, span<const float3> rest_points,
                             span<const float3> rest_normals) {
  const bool have_normals = rest_normals.size() == rest_points.size();
  return BuildTable(muscles, rest_points,
                    std::vector<NormalsOf>(muscles.size(),
                                           NormalsOf{have_normals ? rest_normals : span<const float3>()}));
}

MuscleTable BuildMuscleTable(span<const MuscleSpec> muscles, span<const float3> rest_points,
                             NormalField* field) {
  std::vector<NormalsOf> normals(muscles.size());
  for (size_t m = 0; m < muscles.size(); ++m)
    if (field && muscles[m].motion == MuscleMotion::kTangent)
      normals[m] = NormalsOf{{}, field, muscles[m].tangent_radius};
  return BuildTable(muscles, rest_points, normals);
}

std::vector<uint32_t> CountInfluencedPoints(const MuscleTable& table) {
  std::vector<uint32_t> count(table.muscle_count, 0u);
  for (const MuscleInfluence& e : table.entries)
    if (e.muscle < count.size()) ++count[e.muscle];
  return count;
}

}  // namespace mimetic
