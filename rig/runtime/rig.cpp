#include "rig/runtime/rig.h"

namespace mimetic {

int Rig::FindMuscle(std::string_view name) const {
  for (size_t i = 0; i < muscle_names.size(); ++i)
    if (muscle_names[i] == name) return int(i);
  return -1;
}

}  // namespace mimetic
