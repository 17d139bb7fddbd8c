#include "muscles/offline/muscle_builder.h"

#include "muscles/offline/waters.h"

namespace mimetic {

float3 ApplyMuscleMotion(float3 d, float3 normal, MuscleMotion motion) {
  if (motion == MuscleMotion::kChord) return d;
  return d - Dot(d, normal) * normal;
}

MuscleTable BuildMuscleTable(span<const MuscleSpec> muscles, span<const float3> rest_points,
                             span<const float3> rest_normals) {
  const bool have_normals = rest_normals.size() == rest_points.size();
  MuscleTable table;
  table.muscle_count = uint32_t(muscles.size());
  table.offsets.resize(rest_points.size() + 1);
  for (size_t p = 0; p < rest_points.size(); ++p) {
    table.offsets[p] = uint32_t(table.entries.size());
    for (size_t m = 0; m < muscles.size(); ++m) {
      float3 d = MuscleDisplacement(muscles[m], rest_points[p], muscles[m].strength);
      if (have_normals) d = ApplyMuscleMotion(d, rest_normals[p], muscles[m].motion);
      if (d.x != 0.f || d.y != 0.f || d.z != 0.f) table.entries.push_back({uint32_t(m), d});
    }
  }
  table.offsets[rest_points.size()] = uint32_t(table.entries.size());
  return table;
}

}  // namespace mimetic
