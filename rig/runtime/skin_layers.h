// rig/runtime/skin_layers.h: the one switch set for the skin layers (docs/model.md §1 steps 3-4).
#pragma once

namespace mimetic {

// Which skin layers are on. The same type says what a rig file asks for (RigSpec::layers), what a rig compiled (Rig::layers: a layer is on when the file enables it and it
// has something to do: a non-zero thickness, a non-empty region) and what one evaluation runs
// (EvaluateJob::layers, ANDed with the rig's; the viewer toggles them). Default: all on.
struct SkinLayers {
  bool thickness = true;        // docs/model.md §4
  bool muscle_wrinkles = true;  // docs/model.md §6
  bool curve_wrinkles = true;   // docs/model.md §7-8
};

}  // namespace mimetic
