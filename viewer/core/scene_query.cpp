// viewer/core/scene_query.cpp: see scene_query.h.
#include "viewer/core/scene_query.h"

#include <cmath>

#include "geometry/ray_triangle.h"

namespace mimetic::viewer {

bool PickTriangle(span<const float3> positions, span<const uint32_t> indices,
                  const float3& origin, const float3& direction, PickHit* hit) {
  bool found = false;
  float best = INFINITY;
  const size_t nv = positions.size();
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t ia = indices[t], ib = indices[t + 1], ic = indices[t + 2];
    if (ia >= nv || ib >= nv || ic >= nv) return false;
    float d = 0.f, u = 0.f, w = 0.f;
    if (!RayTriangle(origin, direction, positions[ia], positions[ib], positions[ic], &d, &u, &w,
                     1e-12f) ||
        d >= best)
      continue;
    best = d;
    found = true;
    hit->triangle = uint32_t(t / 3);
    hit->distance = d;
    hit->u = u;
    hit->w = w;
    const float v0 = 1.f - u - w;
    hit->nearest = v0 >= u && v0 >= w ? ia : (u >= w ? ib : ic);
  }
  return found;
}

std::vector<uint32_t> MusclesReachingPoint(const Rig& rig, uint32_t point) {
  std::vector<uint32_t> out;
  const MuscleTable& table = rig.muscles();
  if (point >= table.point_count()) return out;
  for (uint32_t e = table.offsets[point]; e < table.offsets[point + 1]; ++e) {
    const MuscleInfluence& in = table.entries[e];
    if (LengthSquared(in.displacement) > 0.f && (out.empty() || out.back() != in.muscle))
      out.push_back(in.muscle);
  }
  return out;
}

namespace {

struct RegionPrefix {
  const char* prefix;
  const char* region;
};
// Anatomical names of the muscle templates (assets/head/default.template.json, docs/facs.md).
constexpr RegionPrefix kRegions[] = {
    {"frontalis", "brow and forehead"},     {"corrugator", "brow and forehead"},
    {"procerus", "brow and forehead"},      {"orbicularis_oculi", "eyes"},
    {"crows_feet", "eyes"},                 {"levator_palpebrae", "eyes"},
    {"nasalis", "nose"},                    {"levator_labii_alaeque_nasi", "nose"},
    {"zygomaticus", "cheeks"},              {"levator_labii_superioris", "cheeks"},
    {"buccinator", "cheeks"},               {"risorius", "cheeks"},
    {"depressor", "mouth and chin"},        {"mentalis", "mouth and chin"},
    {"orbicularis_oris", "mouth and chin"}, {"platysma", "mouth and chin"},
    {"levator_anguli_oris", "mouth and chin"},
};
constexpr const char* kRegionOrder[] = {"brow and forehead", "eyes", "nose", "cheeks",
                                        "mouth and chin", "other"};

}  // namespace

const char* MuscleRegion(const std::string& muscle_name) {
  for (const RegionPrefix& r : kRegions)
    if (muscle_name.rfind(r.prefix, 0) == 0) return r.region;
  return "other";
}

std::vector<MuscleGroup> GroupMuscles(const std::vector<std::string>& muscle_names) {
  std::vector<MuscleGroup> groups;
  for (const char* region : kRegionOrder) {
    MuscleGroup g{region, {}};
    for (uint32_t m = 0; m < muscle_names.size(); ++m)
      if (std::string(MuscleRegion(muscle_names[m])) == region) g.muscles.push_back(m);
    if (!g.muscles.empty()) groups.push_back(std::move(g));
  }
  return groups;
}

int MirrorMuscle(const std::vector<std::string>& muscle_names, uint32_t muscle) {
  if (muscle >= muscle_names.size()) return -1;
  const std::string& name = muscle_names[muscle];
  if (name.size() < 3 || name[name.size() - 2] != '_') return -1;
  const char side = name.back();
  if (side != 'L' && side != 'R') return -1;
  const std::string other = name.substr(0, name.size() - 1) + (side == 'L' ? 'R' : 'L');
  for (uint32_t m = 0; m < muscle_names.size(); ++m)
    if (muscle_names[m] == other) return int(m);
  return -1;
}

}  // namespace mimetic::viewer
