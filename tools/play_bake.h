// tools/play_bake.h: `mimetic play RIG CLIP --fps F --out FILE.glb`: every frame evaluated
// (over a few threads, one EvaluateContext each) and baked into one .glb (io/gltf_bake.h).
#pragma once

#include <string>
#include <vector>

#include "expressions/runtime/clip.h"
#include "rig/offline/rig_spec.h"
#include "rig/runtime/rig.h"
#include "rig/runtime/skin_layers.h"

namespace mimetic::tools {

struct PlayBakeRequest {
  const Rig* rig = nullptr;
  const RigSpec* spec = nullptr;      // for CheckPosedFinite's messages
  const CompiledClip* clip = nullptr;
  std::vector<double> times;          // seconds, frame k at times[k]
  SkinLayers layers;
  std::string out;                    // the .glb
  std::string rig_path, clip_path;    // for messages
  double fps = 30;
  double metres_per_unit = 0.001;
  bool normals = true;                // NORMAL and its deltas
  // --tension (docs/tension.md "Baking"): each frame's (r - 1, eps) per vertex as the glb's
  // `_TENSION` attribute and target deltas, and, when the rig has tension regions, their
  // per-frame weights in `regions_out` (JSON: times and one weight curve per region).
  bool tension = false;
  std::string regions_out;            // empty: no region weights file
  bool quiet = false;                 // no progress bar, no summary
  unsigned threads = 0;               // 0: min(hardware threads, 8)
};

// The region-weights file's name for a bake to `glb`: FILE.glb -> FILE.regions.json.
std::string RegionWeightsPath(const std::string& glb);

// Evaluates, bakes, writes atomically, prints the summary (frames, duration, file size,
// vertices moved). Returns the exit status (0, or kExitInput with the messages on stderr).
int PlayBake(const PlayBakeRequest& request);

}  // namespace mimetic::tools
