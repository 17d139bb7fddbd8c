#include "muscles/runtime/muscle_table.h"

namespace mimetic {

uint32_t MuscleTable::CountInfluenced(uint32_t muscle) const {
  uint32_t n = 0;
  for (const MuscleInfluence& e : entries) n += e.muscle == muscle;
  return n;
}

bool MuscleDeformJob::Validate() const {
  if (!table) return false;
  const uint32_t points = table->point_count();
  if (table->offsets.empty() || table->offsets.back() != table->entries.size()) return false;
  if (activations.size() < table->muscle_count) return false;
  if (rest_points.size() < points || out_points.size() < points) return false;
  if (begin > end || end > points) return false;
  return true;
}

bool MuscleDeformJob::Run() const {
  if (!Validate()) return false;
  const uint32_t* offsets = table->offsets.data();
  const MuscleInfluence* entries = table->entries.data();
  const float* act = activations.data();
  for (uint32_t p = begin; p < end; ++p) {
    float3 pos = rest_points[p];
    for (uint32_t e = offsets[p], e_end = offsets[p + 1]; e < e_end; ++e) {
      const float a = ClampOrLow(act[entries[e].muscle], 0.f, 1.f);
      pos += a * entries[e].displacement;
    }
    out_points[p] = pos;
  }
  return true;
}

}  // namespace mimetic
