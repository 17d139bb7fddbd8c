// core/span.h: the runtime's view type. Jobs take spans, own nothing.
#pragma once

#include <span>

namespace mimetic {
template <class T>
using span = std::span<T>;
}  // namespace mimetic
