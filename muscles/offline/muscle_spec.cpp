#include "muscles/offline/muscle_spec.h"

namespace mimetic {

const char* MuscleTypeName(MuscleType type) {
  switch (type) {
    case MuscleType::kLinear: return "linear";
    case MuscleType::kSheet: return "sheet";
  }
  return "unknown";
}

const char* MuscleFalloffName(MuscleFalloff falloff) {
  switch (falloff) {
    case MuscleFalloff::kWaters: return "waters";
    case MuscleFalloff::kSmooth: return "smooth";
  }
  return "unknown";
}

}  // namespace mimetic
