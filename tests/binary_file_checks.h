// tests/binary_file_checks.h: the section-file layout shared by .mrig and .mclip
// (core/binary_sections.h, docs/mrig-format.md, docs/mclip-format.md), decoded here
// independently of the reader, and the truncation check both formats' tests run.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mimetic::test {

inline uint32_t U32At(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | uint8_t(b[at + i]);
  return v;
}
inline uint64_t U64At(const std::string& b, size_t at) {
  return U32At(b, at) | uint64_t(U32At(b, at + 4)) << 32;
}
inline void PutU32(std::string* b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) (*b)[at + i] = char(v >> (8 * i));
}
inline void PutF32(std::string* b, size_t at, float v) {
  PutU32(b, at, std::bit_cast<uint32_t>(v));
}
inline void PutU64(std::string* b, size_t at, uint64_t v) {
  PutU32(b, at, uint32_t(v));
  PutU32(b, at + 4, uint32_t(v >> 32));
}

// One entry of the section table (32 bytes each from byte 40).
struct Entry {
  uint32_t id, element_size;
  uint64_t offset, size, count;
  size_t at;  // where the entry is
};
inline std::vector<Entry> Table(const std::string& b) {
  std::vector<Entry> t;
  for (uint32_t i = 0; i < U32At(b, 12); ++i) {
    const size_t at = 40 + 32 * size_t(i);
    t.push_back({U32At(b, at), U32At(b, at + 4), U64At(b, at + 8), U64At(b, at + 16),
                 U64At(b, at + 24), at});
  }
  return t;
}

// The reader's message for a file cut at byte `cut` (its full section table `table`): a cut
// in the header or the table names them; past the table, the first section in table order
// that no longer fits is named with its offset and size; a cut in the padding after the last
// payload leaves every section whole, and the header's total size is wrong.
inline void ExpectTruncationNamed(const std::vector<Entry>& table, size_t cut,
                                  const std::string& error) {
  SCOPED_TRACE("cut at " + std::to_string(cut) + ": " + error);
  const size_t table_end = 40 + 32 * table.size();
  if (cut < 40) {
    EXPECT_NE(error.find("header"), std::string::npos);
    EXPECT_NE(error.find("truncated"), std::string::npos);
    return;
  }
  if (cut < table_end) {
    EXPECT_NE(error.find("section table at byte 40"), std::string::npos);
    return;
  }
  for (const Entry& e : table)
    if (e.offset + e.size > cut) {
      EXPECT_NE(error.find("(id " + std::to_string(e.id) + ") at byte " +
                           std::to_string(e.offset) + ": its " + std::to_string(e.size) +
                           " bytes extend past the end of the file"),
                std::string::npos);
      return;
    }
  EXPECT_NE(error.find("header at byte 16: total size"), std::string::npos);
}

}  // namespace mimetic::test
