// tests/core/math_test.cpp: FMin / FMax (core/math.h) against the C library's std::fmin and
// std::fmax, bit for bit, over the values where the two could part: NaNs on either side, signed
// zeros both ways round, infinities, denormals and ordinary numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "core/math.h"

namespace mimetic {
namespace {

uint32_t Bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

TEST(FMinFMax, EqualTheCLibraryBitForBit) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float den = std::numeric_limits<float>::denorm_min();
  const std::vector<float> values{0.f,  -0.f,  1.f,  -1.f, 2.5f, -2.5f, inf, -inf,
                                  den,  -den,  1e38f, -1e-38f, nan, -nan};
  // volatile: the library's own functions, not a constant the compiler folded.
  float (*volatile lib_min)(float, float) = [](float a, float b) { return std::fmin(a, b); };
  float (*volatile lib_max)(float, float) = [](float a, float b) { return std::fmax(a, b); };
  for (float a : values)
    for (float b : values) {
      const float m = lib_min(a, b), x = lib_max(a, b);
      if (std::isnan(m)) {
        EXPECT_TRUE(std::isnan(FMin(a, b))) << a << " " << b;
      } else {
        EXPECT_EQ(Bits(FMin(a, b)), Bits(m)) << a << " " << b;
      }
      if (std::isnan(x)) {
        EXPECT_TRUE(std::isnan(FMax(a, b))) << a << " " << b;
      } else {
        EXPECT_EQ(Bits(FMax(a, b)), Bits(x)) << a << " " << b;
      }
    }
  // By hand: a NaN is ignored, the smaller or larger is kept.
  EXPECT_EQ(FMin(nan, 3.f), 3.f);
  EXPECT_EQ(FMin(3.f, nan), 3.f);
  EXPECT_EQ(FMax(-inf, nan), -inf);
  EXPECT_EQ(FMin(-1.f, 2.f), -1.f);
  EXPECT_EQ(FMax(-1.f, 2.f), 2.f);
}

}  // namespace
}  // namespace mimetic
