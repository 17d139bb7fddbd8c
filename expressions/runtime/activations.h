// expressions/runtime/activations.h: the activation span every frame starts from.
#pragma once

#include "core/span.h"

namespace mimetic {

// out[i] = in[i] clamped to [0, 1], NaN -> 0 (DESIGN.md: runtime clamps, never rejects).
// Returns false (and writes nothing) when out is shorter than in.
bool SanitizeActivations(span<const float> in, span<float> out);

}  // namespace mimetic
