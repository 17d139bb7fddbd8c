// rig/offline/jaw_setting.h: `jaw=VALUE` among NAME=VALUE pose settings (mimetic eval --set,
// mimetic-viewer --set): the jaw is not a muscle, so it is taken out before BindActivations.
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "rig/runtime/rig.h"

namespace mimetic {

// Removes `jaw=VALUE` from `sets` (unless the rig has a muscle called jaw) into *jaw: a
// number in [0, 1], for a rig with a jaw. False with the problem recorded otherwise.
bool TakeJawSetting(const Rig& rig, std::vector<std::string>* sets, float* jaw, Diagnostics* diag);

}  // namespace mimetic
