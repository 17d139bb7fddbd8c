// io/arkit_map.h: how a rig makes each of Apple's 52 ARKit blendshapes (JSON, "format":
// "mimetic-arkit-map"): muscle activations per shape, and whether they were solved on a real
// shape, set by hand from anatomy, or cannot be made by the rig's muscles. A face tracker's 52
// coefficients drive the rig through it (docs/arkit.md; assets/arkit/default.arkit.json).
//
//   {"format": "mimetic-arkit-map", "version": 1,
//    "shapes": {"browDownLeft": {"how": "solved", "activations": {"procerus_L": 0.86, ...},
//                                "note": "...", "target": "ict-facekit/arkit/browDown_L.obj",
//                                "mean_distance": 0.027, "neutral_mean_distance": 0.034,
//                                "ratio": 0.79},
//               "browInnerUp": {"how": "anatomy", ...}, "eyeBlinkLeft": {"how": "none", ...},
//               ... every one of the 52 names exactly once}}
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "core/span.h"

namespace mimetic {

// Apple's 52 ARFaceAnchor blendshape names, in Apple's order (eyes, mouth and jaw, brows,
// cheeks, nose, tongue). "Left" / "Right" are the subject's sides (ICT-FaceKit's _L / _R).
span<const char* const> ArkitShapeNames();

struct ArkitShape {
  enum class How { kSolved, kAnatomy, kNone };
  std::string name;  // one of ArkitShapeNames()
  How how = How::kNone;
  std::vector<std::pair<std::string, float>> activations;  // muscle name -> [0, 1]
  std::string note;  // why (anatomy, none) or what the solve shows
  // kSolved only: the real shape solved (relative to the data folder) and the result's mean
  // distance to it, the neutral's, and their ratio (mimetic solve / compare, docs/model.md §13).
  std::string target;
  double mean_distance = 0, neutral_mean_distance = 0, ratio = 0;
};

const char* ArkitHowName(ArkitShape::How how);  // "solved", "anatomy", "none"

// Parses a map (the table in io/arkit_map.cpp, the schema
// assets/schema/mimetic-arkit-map.schema.json) into the 52 shapes in Apple's order. Records
// every problem with its JSON path: wrong format or version, a missing ARKit name, an unknown
// one (with the closest names), a name twice, a missing or unknown "how", activations not an
// object or not in [0, 1], a "none" shape with a non-zero activation, a solved one without its
// target and distances or whose ratio is not mean / neutral. False on any error.
bool ParseArkitMap(const std::string& text, const std::string& where,
                   std::vector<ArkitShape>* out, Diagnostics* diag);
bool LoadArkitMap(const std::string& path, std::vector<ArkitShape>* out, Diagnostics* diag);

std::string ArkitMapToJson(const std::vector<ArkitShape>& shapes);

// Writes the file atomically. Refuses (false, naming the shape) anything the parser would
// refuse: not exactly the 52 names once each, activations outside [0, 1] or repeated, a "none"
// shape with a non-zero activation, a solved one without its target.
bool SaveArkitMap(const std::string& path, const std::vector<ArkitShape>& shapes,
                  Diagnostics* diag);

// Every muscle named is one of `muscle_names` (a rig's): an error per unknown name with the
// closest names. False when any was unknown.
bool CheckArkitMuscles(const std::vector<ArkitShape>& shapes,
                       const std::vector<std::string>& muscle_names, const std::string& where,
                       Diagnostics* diag);

}  // namespace mimetic
