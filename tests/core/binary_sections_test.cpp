// core/binary_sections.h's checksum: the one- and four-lane rules computed here from their
// definition (docs/mrig-format.md) on a hand-made byte string, Checksummer fed in pieces equal
// to the whole-file value, and ReadFileBuffer's checksum of a file read in 1 MiB pieces equal to
// Checksum of its bytes.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/binary_sections.h"
#include "test_support.h"

namespace mimetic::binary {
namespace {

// The definition, word by word, with no shared code: FNV-1a's basis and prime, the state
// rotated by 23 before each xor; word 3 as 0; the tail zero padded; four lanes: word i into lane
// i % 4 (lane l from basis ^ l), then the four lanes through the same step from the basis.
uint64_t Reference(const std::vector<uint8_t>& file, bool four) {
  if (file.size() < 40) return 0;
  const uint64_t basis = 0xcbf29ce484222325ull, prime = 0x100000001b3ull;
  std::vector<uint8_t> padded = file;
  padded.resize((file.size() + 7) / 8 * 8, 0);
  uint64_t lane[4] = {basis, basis ^ 1, basis ^ 2, basis ^ 3};
  for (size_t i = 0; i < padded.size() / 8; ++i) {
    uint64_t w = 0;
    for (int b = 7; b >= 0; --b) w = w << 8 | padded[8 * i + size_t(b)];
    if (i == 3) w = 0;
    uint64_t& h = lane[four ? i % 4 : 0];
    h = ((h << 23 | h >> 41) ^ w) * prime;
  }
  if (!four) return lane[0];
  uint64_t h = basis;
  for (uint64_t l : lane) h = ((h << 23 | h >> 41) ^ l) * prime;
  return h;
}

std::vector<uint8_t> Bytes(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> b(n);
  for (uint8_t& x : b) x = uint8_t(rng());
  return b;
}

TEST(Checksum, OneAndFourLanesMatchTheirDefinition) {
  for (size_t n : {0u, 39u, 40u, 41u, 47u, 48u, 64u, 71u, 1000u, 4099u}) {
    const std::vector<uint8_t> b = Bytes(n, uint32_t(n));
    EXPECT_EQ(Checksum({b.data(), b.size()}, 1), Reference(b, false)) << n;
    EXPECT_EQ(Checksum({b.data(), b.size()}, 4), Reference(b, true)) << n;
    if (n >= 40) {
      EXPECT_NE(Checksum({b.data(), b.size()}, 1), Checksum({b.data(), b.size()}, 4)) << n;
    }
  }
  // The checksum field itself (bytes 24-31) does not count; every other byte does.
  std::vector<uint8_t> b = Bytes(200, 7);
  const uint64_t h = Checksum({b.data(), b.size()}, 4);
  b[27] ^= 0xff;
  EXPECT_EQ(Checksum({b.data(), b.size()}, 4), h);
  b[27] ^= 0xff;
  for (size_t at : {0u, 23u, 32u, 100u, 199u}) {
    b[at] ^= 1;
    EXPECT_NE(Checksum({b.data(), b.size()}, 4), h) << at;
    b[at] ^= 1;
  }
}

TEST(Checksum, PiecesGiveTheWholeFilesValue) {
  const std::vector<uint8_t> b = Bytes(10007, 3);
  for (int lanes : {1, 4})
    for (size_t piece : {32u, 64u, 96u, 1024u, 4096u}) {
      Checksummer sum(lanes);
      for (size_t at = 0; at < b.size(); at += piece)
        sum.Update(b.data() + at, std::min(piece, b.size() - at));
      EXPECT_EQ(sum.Finish(), Reference(b, lanes == 4)) << lanes << " lanes, pieces of " << piece;
    }
  Checksummer short_file(4);
  short_file.Update(b.data(), 39);
  EXPECT_EQ(short_file.Finish(), 0u);
}

TEST(Checksum, ReadFileBufferChecksumsWhileReading) {
  // A header of a format whose major version 2 has four lanes, then 3 MiB + 5 bytes (pieces of
  // 1 MiB and a partial last word).
  const SectionDesc none[] = {{1, "x", 4, 0, false}};
  const Format format{{'T', 'E', 'S', 'T'}, 2, 0, ".test", "test file", "rebuild", none, 1, 2};
  for (uint16_t major : {1, 2}) {
    std::vector<uint8_t> b = Bytes((size_t{3} << 20) + 5, major);
    b[4] = uint8_t(major), b[5] = 0;
    const std::string path = test::TempDir() + "/f" + std::to_string(major) + ".test";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()),
                                                std::streamsize(b.size()));
    std::unique_ptr<uint8_t[]> out;
    size_t size = 0;
    uint64_t checksum = 0;
    std::string error;
    ASSERT_TRUE(ReadFileBuffer(path, format, size_t{1} << 30, &out, &size, &checksum, &error))
        << error;
    ASSERT_EQ(size, b.size());
    EXPECT_TRUE(std::equal(b.begin(), b.end(), out.get()));
    EXPECT_EQ(checksum, Reference(b, major == 2)) << "major " << major;
    EXPECT_FALSE(ReadFileBuffer(path + ".missing", format, size_t{1} << 30, &out, &size,
                                &checksum, &error));
    EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace mimetic::binary
