// rig/offline/jaw_setting.cpp: see jaw_setting.h.
#include "rig/offline/jaw_setting.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace mimetic {

bool TakeJawSetting(const Rig& rig, std::vector<std::string>* sets, float* jaw, Diagnostics* diag) {
  if (rig.FindMuscle("jaw") >= 0) return true;
  bool ok = true;
  for (auto it = sets->begin(); it != sets->end();) {
    if (it->rfind("jaw=", 0) != 0) {
      ++it;
      continue;
    }
    const std::string value = it->substr(4), where = "--set " + *it;
    it = sets->erase(it);
    char* end = nullptr;
    errno = 0;
    const double v = value.empty() ? NAN : std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      diag->Error(where, "value '" + value + "' is not a finite number (expected a number in "
                         "[0, 1], the jaw opening as a fraction of its range)");
      ok = false;
    } else if (v < 0.0 || v > 1.0) {
      diag->Error(where, "value " + value + " is outside [0, 1] (the jaw opening is a fraction "
                         "of the rig's jaw range)");
      ok = false;
    } else if (rig.jaw().empty()) {
      diag->Error(where, "the rig has no jaw (docs/rig-format.md, `jaw`); expected a rig "
                         "file with a jaw block, e.g. one fitted from a template with one");
      ok = false;
    } else {
      *jaw = float(v);
    }
  }
  return ok;
}

}  // namespace mimetic
