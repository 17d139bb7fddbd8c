#include "expressions/runtime/clip.h"

namespace mimetic {

size_t CompiledClip::ByteSize() const {
  return sizeof(CompiledClip) + name_.capacity() + kinds_.capacity() * sizeof(ClipChannelKind) +
         layers_.capacity() * sizeof(ClipLayer) + targets_.capacity() * sizeof(uint32_t) +
         key_offsets_.capacity() * sizeof(uint32_t) + key_times_.capacity() * sizeof(float) +
         key_values_.capacity() * sizeof(float) + key_tangents_.capacity() * sizeof(float) +
         key_interps_.capacity() * sizeof(KeyInterp) +
         expression_activations_.capacity() * sizeof(float) + expression_masks_.capacity() +
         expression_jaws_.capacity() * sizeof(float) + expression_jaw_masks_.capacity();
}

}  // namespace mimetic
