// expressions/offline/activation_binding.h: names -> the activation span (offline binding).
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"

namespace mimetic {

// Parses "NAME=VALUE" assignments against the rig's muscle names and fills `out` (one value
// per muscle, rig order; unassigned muscles are 0). NAME sets both NAME_L and NAME_R when the
// rig has no muscle called NAME but has those two. Records an error for: a missing '=', an
// unknown name (listing the closest names), a value that is not a finite number or lies
// outside [0, 1], and a name assigned twice. Returns false when any error was recorded.
bool BindActivations(const std::vector<std::string>& muscle_names,
                     const std::vector<std::string>& assignments, std::vector<float>* out,
                     Diagnostics* diag);

// The (at most three) names of `names` closest to `wrong`, comma-separated: those that contain
// it first, then by edit distance (for "unknown name" messages).
std::string ClosestNames(const std::vector<std::string>& names, const std::string& wrong);

}  // namespace mimetic
