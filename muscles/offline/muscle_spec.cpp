#include "muscles/offline/muscle_spec.h"

namespace mimetic {

const char* MuscleTypeName(MuscleType type) {
  switch (type) {
    case MuscleType::kLinear: return "linear";
    case MuscleType::kSheet: return "sheet";
  }
  return "unknown";
}

}  // namespace mimetic
