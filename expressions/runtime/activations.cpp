#include "expressions/runtime/activations.h"

#include "core/math.h"

namespace mimetic {

bool SanitizeActivations(span<const float> in, span<float> out) {
  if (out.size() < in.size()) return false;
  for (size_t i = 0; i < in.size(); ++i) out[i] = ClampOrLow(in[i], 0.f, 1.f);
  return true;
}

}  // namespace mimetic
