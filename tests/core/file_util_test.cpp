// Tests for core/file_util (ReadFile's regular-file check and caps, WriteFileAtomic's stale
// temporary files) and the printing cap of core/diagnostics.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/diagnostics.h"
#include "core/file_util.h"
#include "test_support.h"

namespace mimetic {
namespace {

void Write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string OnlyMessage(const Diagnostics& d) {
  return d.items().size() == 1 ? d.items()[0].where + ": " + d.items()[0].what : d.Format();
}

TEST(ReadFile, ReadsARegularFileExactly) {
  const std::string path = test::TempDir() + "/a.bin";
  const std::string bytes("ab\0cd\n", 6);
  Write(path, bytes);
  std::string out;
  Diagnostics d;
  ASSERT_TRUE(ReadFile(path, &out, &d, 6, "test file")) << d.Format();
  EXPECT_EQ(out, bytes);
  EXPECT_TRUE(d.empty());
}

TEST(ReadFile, RefusesADirectoryAFifoAndADevice) {
  const std::string dir = test::TempDir();
  std::string out = "untouched";
  Diagnostics d;
  EXPECT_FALSE(ReadFile(dir, &out, &d, kMaxMeshFileBytes, "mesh file"));
  EXPECT_EQ(OnlyMessage(d), dir + ": is not a regular file (it is a directory; expected a mesh file)");
  EXPECT_EQ(out, "untouched");

  // A FIFO without a writer: refused at once (opening it for reading would block forever).
  const std::string fifo = dir + "/pipe.glb";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  d.Clear();
  EXPECT_FALSE(ReadFile(fifo, &out, &d, kMaxMeshFileBytes, "glb mesh file"));
  EXPECT_EQ(OnlyMessage(d),
            fifo + ": is not a regular file (it is a FIFO (named pipe); expected a glb mesh file)");

  // /dev/zero would be read until memory runs out.
  d.Clear();
  EXPECT_FALSE(ReadFile("/dev/zero", &out, &d, kMaxImageFileBytes, "image file"));
  EXPECT_EQ(OnlyMessage(d),
            "/dev/zero: is not a regular file (it is a character device; expected an image file)");
  EXPECT_EQ(CheckRegularFile("/dev/zero", 10, "rig file"),
            "is not a regular file (it is a character device; expected a rig file)");
}

TEST(ReadFile, RefusesAFileOverItsCapBeforeReadingIt) {
  const std::string path = test::TempDir() + "/big.json";
  Write(path, std::string(2 * kMiB + 1, ' '));
  std::string out;
  Diagnostics d;
  EXPECT_FALSE(ReadFile(path, &out, &d, 2 * kMiB, "JSON file"));
  EXPECT_EQ(OnlyMessage(d),
            path + ": is larger than the 2 MiB limit for a JSON file (2097153 bytes)");
  d.Clear();
  EXPECT_TRUE(ReadFile(path, &out, &d, 2 * kMiB + 1, "JSON file"));
  EXPECT_EQ(out.size(), 2 * kMiB + 1);
  // The caps of docs/errors.md.
  EXPECT_EQ(kMaxJsonFileBytes, size_t{64} << 20);
  EXPECT_EQ(kMaxMeshFileBytes, size_t{1024} << 20);
  EXPECT_EQ(kMaxImageFileBytes, size_t{256} << 20);
}

TEST(ReadFile, MissingFileSaysCannotOpen) {
  std::string out;
  Diagnostics d;
  EXPECT_FALSE(ReadFile("/nonexistent/x.rig.json", &out, &d));
  EXPECT_EQ(OnlyMessage(d), "/nonexistent/x.rig.json: cannot open: No such file or directory");
}

TEST(WriteFileAtomic, RemovesStaleTemporariesOfDeadWritersOnly) {
  const std::string dir = test::TempDir();
  const std::string target = dir + "/out.glb";
  // pid 999999999 is above any pid_max, so its writer is dead; the parent process is alive.
  const std::string dead = target + ".tmp999999999";
  const std::string alive = target + ".tmp" + std::to_string(::getppid());
  const std::string other = target + ".tmpx1";  // not our pattern
  const std::string other_target = dir + "/other.glb.tmp999999999";
  for (const std::string& p : {dead, alive, other, other_target}) Write(p, "partial");
  Diagnostics d;
  ASSERT_TRUE(WriteFileAtomic(target, "new bytes", &d)) << d.Format();
  EXPECT_FALSE(std::filesystem::exists(dead));
  EXPECT_TRUE(std::filesystem::exists(alive));
  EXPECT_TRUE(std::filesystem::exists(other));
  EXPECT_TRUE(std::filesystem::exists(other_target));
  EXPECT_FALSE(std::filesystem::exists(target + ".tmp" + std::to_string(::getpid())));
  std::string out;
  ASSERT_TRUE(ReadFile(target, &out, &d));
  EXPECT_EQ(out, "new bytes");
}

TEST(Diagnostics, FormatPrintsAtMostFiftyLinesAndCountsTheRest) {
  Diagnostics d;
  for (int i = 0; i < 200000; ++i) d.Error("muscles[" + std::to_string(i) + "]", "bad");
  d.Warning("", "late warning");
  const std::string text = d.Format();
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 51u);
  EXPECT_NE(text.find("error: muscles[49]: bad\n"), std::string::npos);
  EXPECT_EQ(text.find("muscles[50]"), std::string::npos);
  EXPECT_NE(text.find("... and 199951 more (199950 errors, 1 warnings) not shown\n"),
            std::string::npos);
  EXPECT_EQ(d.Format(size_t(-1)).size() > text.size(), true);
}

}  // namespace
}  // namespace mimetic
