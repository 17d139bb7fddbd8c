// expressions/offline/arkit_import.h: a face-capture take (ARKit blendshape weights per frame)
// turned into a clip of muscle channels through an ARKit map (docs/arkit.md, "Importing a
// take"). The take is read by io/arkit_take.h, the map by io/arkit_map.h; this file knows
// neither format.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "expressions/offline/clip_spec.h"

namespace mimetic {

// A take: frames of weights, one column per channel as the file names it.
struct ArkitTake {
  std::vector<std::string> names;  // channel names as written ("jawOpen", "JawOpen", "HeadYaw")
  std::vector<float> times;        // seconds from the first frame (0), strictly increasing
  std::vector<float> weights;      // frame-major: weights[f * names.size() + c]; ARKit
                                   // channels in [0, 1]; other channels any finite number
};

// How the map makes one ARKit shape (io/arkit_map.h's ArkitShape, reduced to what the import
// reads).
struct ArkitShapeActivations {
  std::string name;  // Apple's name ("jawOpen")
  bool none = false; // "how": "none": the rig's muscles cannot make it
  std::vector<std::pair<std::string, float>> activations;  // muscle name -> [0, 1]
};

// A take channel the import could not use.
struct ArkitUnmapped {
  std::string name;      // as the take writes it
  bool none = false;     // true: an ARKit shape the map marks "none"; false: not an ARKit name
  bool no_jaw = false;   // true: the map drives only the jaw with it, and the rig has none
  size_t nonzero = 0;    // frames where its weight is not 0
};

struct ArkitImport {
  ClipSpec clip;                        // muscle channels only, linear keys, end "clamp"
  std::vector<ArkitUnmapped> unmapped;  // in take column order
};

// The index in `shapes` of a take channel's name: Apple's name, or the same with its first
// letter in the other case (Live Link Face's "EyeBlinkLeft"). -1 when none.
int FindArkitShape(const std::vector<ArkitShapeActivations>& shapes, const std::string& name);

// The activations of one frame (`weights`: one per take channel), rig order: per muscle m,
// clamp(sum over the take's mapped channels c of weight_c * map_c(m), 0, 1). `channel_shape`
// is FindArkitShape per take channel.
std::vector<float> ArkitFrameActivations(const std::vector<ArkitShapeActivations>& shapes,
                                         const std::vector<int>& channel_shape,
                                         const std::vector<std::string>& muscle_names,
                                         const float* weights);

// Drops the keys of a linear channel that the line between the last key kept and the next key
// reproduces within `tolerance`, together with every key dropped since (so no dropped sample
// is further than `tolerance` from the result). The first and last keys stay.
void ReduceLinearKeys(std::vector<ClipKeySpec>* keys, float tolerance = 1e-4f);

// The clip of a take: one muscle channel (rig order) per muscle some frame activates, a linear
// key per frame (then ReduceLinearKeys), duration the last frame's time. Errors: a map muscle
// not in `muscle_names` (a map for another rig), a take without frames. `unmapped` lists the
// channels that are not ARKit names or that the map marks "none".
bool ImportArkitTake(const ArkitTake& take, const std::vector<ArkitShapeActivations>& shapes,
                     const std::vector<std::string>& muscle_names, const std::string& clip_name,
                     ArkitImport* out, Diagnostics* diag);

// The one warning text for `unmapped` ("" when empty): "3 channels are not used: HeadYaw (120
// non-zero frames), ... (not ARKit blendshape names); eyeBlinkLeft (40 non-zero frames) (the
// map marks them \"none\": the rig cannot make them)".
std::string ArkitUnmappedWarning(const std::vector<ArkitUnmapped>& unmapped);

}  // namespace mimetic
