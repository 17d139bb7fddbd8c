#include "fitting/anatomy.h"

#include <cstdio>

#include "core/strings.h"
#include "fitting/landmarks.h"
#include "muscles/offline/muscle_builder.h"
#include "muscles/offline/waters.h"

namespace mimetic {
namespace {

// Zhang 2005 Fig. 1 and Bando 2003 §6 for the first twelve; the four added for the fidelity
// issue (docs/fidelity.md) follow the FACS action units they make: levator labii superioris
// AU10 (upper lip up), depressor labii inferioris AU16 (lower lip down), buccinator AU14
// (dimple: the corner pulled back and out), platysma AU20-like stretch (corner down and out);
// the lateral fibres of orbicularis oculi's orbital part, the brow lowerer of AU4 beside the
// corrugator (a sphincter, stood in for by one linear muscle on each side), lower the outer brow.
const MuscleAnatomy kAnatomy[] = {
    {"frontalis_inner", 22, 0, +1, "raises the inner brow"},
    {"frontalis_major", 24, 0, +1, "raises the brow"},
    {"frontalis_outer", 26, 0, +1, "raises the outer brow"},
    {"corrugator_supercilii", 23, -1, -1, "pulls the brow medially and down"},
    {"procerus", -1, 0, -1, "lowers the glabella"},
    {"nasalis", -1, +1, -1, "flares the ala out and down"},
    {"levator_labii_alaeque_nasi", 35, 0, +1, "raises the ala and the upper lip"},
    {"zygomaticus_minor", 53, 0, +1, "raises the upper lip"},
    {"zygomaticus_major", 54, +1, +1, "pulls the mouth corner up and out"},
    {"risorius", 54, +1, 0, "pulls the mouth corner out"},
    {"depressor_anguli_oris", 54, 0, -1, "pulls the mouth corner down"},
    {"mentalis", -1, 0, +1, "raises the chin"},
    {"levator_labii_superioris", 52, 0, +1, "raises the upper lip"},
    {"depressor_labii_inferioris", 56, 0, -1, "lowers the lower lip"},
    {"buccinator", 54, +1, 0, "pulls the mouth corner back and out"},
    {"platysma", 54, 0, -1, "pulls the mouth corner down and out"},
    {"orbicularis_oculi_lateral", 26, 0, -1, "lowers the outer brow"},
};

std::string BaseName(const std::string& name) {
  if (name.size() > 2 && (EndsWith(name, "_L") || EndsWith(name, "_R")))
    return name.substr(0, name.size() - 2);
  return name;
}

}  // namespace

span<const MuscleAnatomy> DefaultMuscleAnatomy() {
  return span<const MuscleAnatomy>(kAnatomy, sizeof(kAnatomy) / sizeof(kAnatomy[0]));
}

const MuscleAnatomy* FindMuscleAnatomy(const std::string& muscle_name) {
  const std::string base = BaseName(muscle_name);
  for (const MuscleAnatomy& a : kAnatomy)
    if (base == a.muscle) return &a;
  return nullptr;
}

AnatomyProbe FindAnatomyProbe(const MuscleAnatomy& a, const std::string& muscle_name,
                              const MeshData& head, span<const float3> landmarks,
                              span<const PlacedPoint> points) {
  AnatomyProbe probe;
  const bool right = EndsWith(muscle_name, "_R");
  float3 target;
  bool have = false;
  if (a.probe >= 0) {
    const size_t l = size_t(right ? IbugMirrorLandmark(a.probe) : a.probe);
    if (l < landmarks.size()) target = landmarks[l], have = true;
  } else {
    for (const PlacedPoint& p : points)
      if (p.muscle == muscle_name && p.role == "insertion") target = p.surface, have = true;
  }
  if (!have) return probe;
  float best = 1e30f;
  for (uint32_t v = 0; v < head.vertex_count(); ++v) {
    const float d = LengthSquared(head.positions[v] - target);
    if (d < best) best = d, probe.vertex = v, probe.found = true;
  }
  return probe;
}

std::string CheckMuscleAnatomy(const MuscleAnatomy& a, const MuscleSpec& muscle,
                               const FaceFrame& frame, float3 probe_position, float3 normal,
                               float min_fraction) {
  const float3 d = ApplyMuscleMotion(MuscleDisplacement(muscle, probe_position, muscle.strength),
                                     normal, muscle.motion);
  const float sign = EndsWith(muscle.name, "_R") ? -1.f : 1.f;  // lateral = +x on the left
  const float lateral = sign * Dot(d, frame.x), up = Dot(d, frame.y);
  const float need = min_fraction * muscle.strength;
  char buf[256];
  if (a.lateral != 0 && !(float(a.lateral) * lateral > need)) {
    std::snprintf(buf, sizeof buf, "%s %s, but moves its probe %.4g %s (at least %.4g expected)",
                  muscle.name.c_str(), a.action, double(lateral),
                  a.lateral > 0 ? "laterally" : "laterally (medially is -)", double(need));
    return buf;
  }
  if (a.up != 0 && !(float(a.up) * up > need)) {
    std::snprintf(buf, sizeof buf, "%s %s, but moves its probe %.4g up (%s%.4g expected)",
                  muscle.name.c_str(), a.action, double(up), a.up > 0 ? "at least " : "at most -",
                  double(need));
    return buf;
  }
  return "";
}

std::vector<MuscleRegion> DefaultMuscleRegions() {
  std::vector<MuscleRegion> out;
  for (const char* side : {"_L", "_R"}) {
    const std::string s = side;
    out.push_back({"brow" + s,
                   {"frontalis_inner" + s, "frontalis_major" + s, "frontalis_outer" + s,
                    "corrugator_supercilii" + s, "procerus" + s, "orbicularis_oculi_lateral" + s}});
    out.push_back({"upper mouth" + s,
                   {"nasalis" + s, "levator_labii_alaeque_nasi" + s, "zygomaticus_minor" + s,
                    "zygomaticus_major" + s, "levator_labii_superioris" + s, "risorius" + s}});
    out.push_back({"lower mouth" + s,
                   {"risorius" + s, "depressor_anguli_oris" + s, "mentalis" + s,
                    "depressor_labii_inferioris" + s, "buccinator" + s, "platysma" + s}});
  }
  out.push_back({"glabella (both sides)",
                 {"frontalis_inner_L", "frontalis_inner_R", "corrugator_supercilii_L",
                  "corrugator_supercilii_R", "procerus_L", "procerus_R"}});
  out.push_back({"nose and upper lip (both sides)",
                 {"nasalis_L", "nasalis_R", "levator_labii_alaeque_nasi_L",
                  "levator_labii_alaeque_nasi_R", "zygomaticus_minor_L", "zygomaticus_minor_R"}});
  out.push_back({"chin (both sides)",
                 {"mentalis_L", "mentalis_R", "depressor_anguli_oris_L", "depressor_anguli_oris_R",
                  "depressor_labii_inferioris_L", "depressor_labii_inferioris_R"}});
  return out;
}

}  // namespace mimetic
