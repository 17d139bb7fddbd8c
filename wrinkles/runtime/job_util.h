// wrinkles/runtime/job_util.h: validation helpers shared by the wrinkle jobs (internal).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/span.h"

namespace mimetic::detail {

// True when every index in `indices` is < n.
inline bool IndicesBelow(span<const uint32_t> indices, size_t n) {
  for (uint32_t i : indices) {
    if (i >= n) return false;
  }
  return true;
}

// Rows [begin, end) of a CSR table: begin <= end, offsets holds end + 1 entries, is
// non-decreasing over [begin, end], and offsets[end] <= items.
inline bool RowsValid(size_t begin, size_t end, span<const uint32_t> offsets, size_t items) {
  if (begin > end || offsets.size() < end + 1) return false;
  for (size_t i = begin; i < end; ++i) {
    if (offsets[i] > offsets[i + 1]) return false;
  }
  return offsets[end] <= items;
}

}  // namespace mimetic::detail
