// tests/fitting/landmarks_test.cpp: the iBUG-68 scheme (fitting/landmarks.h). The landmark
// file format is tested in tests/io/landmarks_file_test.cpp.
#include <gtest/gtest.h>

#include "fitting/landmarks.h"

namespace mimetic {
namespace {

TEST(MuscleTemplate, IbugMirrorIsAnInvolutionWithTheRightPairs) {
  EXPECT_EQ(IbugMirrorLandmark(0), 16);
  EXPECT_EQ(IbugMirrorLandmark(36), 45);
  EXPECT_EQ(IbugMirrorLandmark(39), 42);
  EXPECT_EQ(IbugMirrorLandmark(48), 54);
  EXPECT_EQ(IbugMirrorLandmark(31), 35);
  EXPECT_EQ(IbugMirrorLandmark(61), 63);
  EXPECT_EQ(IbugMirrorLandmark(65), 67);
  for (int m : {8, 27, 28, 29, 30, 33, 51, 57, 62, 66}) EXPECT_EQ(IbugMirrorLandmark(m), m);
  for (int i = 0; i < 68; ++i) EXPECT_EQ(IbugMirrorLandmark(IbugMirrorLandmark(i)), i);
  EXPECT_EQ(IbugMirrorLandmark(68), -1);
  EXPECT_EQ(IbugMirrorLandmark(-1), -1);
}

}  // namespace
}  // namespace mimetic
