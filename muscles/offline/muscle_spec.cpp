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

const char* MuscleMotionName(MuscleMotion motion) {
  switch (motion) {
    case MuscleMotion::kChord: return "chord";
    case MuscleMotion::kTangent: return "tangent";
  }
  return "unknown";
}

}  // namespace mimetic
