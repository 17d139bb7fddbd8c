// Tests for io/image: decoding from memory, stb's failure reasons in words, and the file
// boundary of LoadGrayImage (regular files only).
#include <gtest/gtest.h>

#include <string>

#include "core/file_util.h"
#include "io/image.h"
#include "test_support.h"

namespace mimetic {
namespace {

std::string Seed(const std::string& name) {
  std::string bytes;
  Diagnostics d;
  EXPECT_TRUE(ReadFile(test::SourceDir() + "/fuzz/seeds/" + name, &bytes, &d)) << d.Format();
  return bytes;
}

TEST(DecodeGrayImage, ReadsTheSeedPng) {
  GrayImage image;
  std::string reason;
  ASSERT_TRUE(DecodeGrayImage(Seed("grey4x4.png"), &image, &reason)) << reason;
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 4);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(image.pixels[i], 16 * i) << i;  // 0, 16, ..., 240
}

TEST(DecodeGrayImage, GivesStbsReasonInWords) {
  const std::string png = Seed("grey4x4.png");
  GrayImage image;
  std::string reason;
  EXPECT_FALSE(DecodeGrayImage(png.substr(0, 60), &image, &reason));
  EXPECT_EQ(reason, "truncated image data (the file ends early) (stb_image: outofdata)");
  EXPECT_FALSE(DecodeGrayImage("plain text", &image, &reason));
  EXPECT_EQ(reason, "not an image format stb_image reads (stb_image: unknown image type)");
  EXPECT_FALSE(DecodeGrayImage("", &image, &reason));
  EXPECT_EQ(reason, "the file is empty");
}

TEST(LoadGrayImage, NamesTheFileAndRefusesADirectory) {
  const std::string dir = test::TempDir();
  GrayImage image;
  Diagnostics d;
  EXPECT_FALSE(LoadGrayImage(dir, "thickness.path", "thickness image", &image, &d));
  EXPECT_EQ(d.Format(), "error: thickness.path: cannot read thickness image '" + dir +
                            "': is not a regular file (it is a directory; expected an image "
                            "file) (expected a PNG, JPEG, TGA or BMP image)\n");
}

}  // namespace
}  // namespace mimetic
