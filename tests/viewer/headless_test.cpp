// mimetic-viewer headless (docs/viewer.md "Headless"): screenshots under xvfb-run with Mesa.
// The sample head's image is not blank; Surprise at its peak changes the forehead and leaves the
// chin; an overlay differs from the shading; a broken rig exits 1 with its message; a missing
// rig on the command line opens the window (still running when the test stops it).
// Without xvfb-run the tests skip (CI, which installs it, fails instead).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/image.h"
#include "io/clip_file.h"
#include "io/image.h"
#include "io/mesh_io.h"
#include "sample_rig.h"
#include "test_support.h"

namespace mimetic::viewer {
namespace {

bool HaveXvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

#define REQUIRE_XVFB()                                                                      \
  do {                                                                                      \
    if (!HaveXvfb()) {                                                                      \
      if (std::getenv("CI")) FAIL() << "xvfb-run is missing (bash tools/install-deps.sh)";  \
      GTEST_SKIP() << "xvfb-run is missing (bash tools/install-deps.sh installs it)";       \
    }                                                                                       \
  } while (0)

// Leak detection is off for the viewer's process only: under Xvfb, LeakSanitizer reports two
// 56-byte callocs made from an "<unknown module>" (the Mesa DRI driver that libGL dlopens and
// unloads at exit, so neither a frame nor a suppression can name it). The viewer's own memory is
// still checked by AddressSanitizer (bounds, use after free) and UBSan here, and by the GL-free
// tests of viewer_core (tests/viewer/*_test.cpp but this one), which run with leak detection.
const char* kViewer = "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 xvfb-run -a ";

// xvfb-run itself fails now and then when tests run in parallel: it exits 5 ("problem while
// cleaning up temporary directory") after the viewer's own run, or 1 when Xvfb does not start.
// Both print "xvfb-run: error"; the viewer never does, so such a run is repeated (twice at most)
// and the viewer's own exit codes are still the ones the tests check.
test::ToolResult RunViewer(const std::vector<std::string>& args) {
  test::ToolResult r;
  for (int attempt = 0; attempt < 3; ++attempt) {
    r = test::RunCommand(kViewer + test::ShellQuote(MIMETIC_VIEWER_PATH), args);
    if (r.output.find("xvfb-run: error") == std::string::npos) break;
  }
  return r;
}

std::string Head() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }
std::string Clip(const std::string& name) {
  return test::SourceDir() + "/assets/clips/" + name + ".clip.json";
}

GrayImage Screenshot(const std::vector<std::string>& args, const std::string& name) {
  const std::string out = test::TempDir() + "/" + name + ".png";
  std::vector<std::string> all = args;
  all.insert(all.end(), {"--screenshot", out, "--size", "640x360"});
  const test::ToolResult r = RunViewer(all);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  GrayImage image;
  Diagnostics diag;
  EXPECT_TRUE(LoadGrayImage(out, "test", "screenshot", &image, &diag)) << diag.Format();
  return image;
}

// Rows [top, bottom) of the head's silhouette: pixels that differ from the corner's colour.
struct Box {
  int top = 0, bottom = 0, left = 0, right = 0;
};
Box Silhouette(const GrayImage& g) {
  const int bg = g.pixels[0];
  Box b{g.height, 0, g.width, 0};
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      if (std::abs(int(g.pixels[size_t(y) * g.width + x]) - bg) > 3) {
        b.top = std::min(b.top, y);
        b.bottom = std::max(b.bottom, y + 1);
        b.left = std::min(b.left, x);
        b.right = std::max(b.right, x + 1);
      }
  return b;
}

// Mean absolute difference of two images over rows [y0, y1) and columns [x0, x1).
double MeanDifference(const GrayImage& a, const GrayImage& b, int y0, int y1, int x0, int x1) {
  double sum = 0.0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      sum += std::abs(int(a.pixels[size_t(y) * a.width + x]) - int(b.pixels[size_t(y) * b.width + x]));
  return sum / std::max(1, (y1 - y0) * (x1 - x0));
}

TEST(ViewerHeadless, SampleHeadScreenshotIsNotBlank) {
  REQUIRE_XVFB();
  const GrayImage g = Screenshot({Head()}, "neutral");
  ASSERT_EQ(g.width, 640);
  ASSERT_EQ(g.height, 360);
  const Box b = Silhouette(g);
  // The framed head spans most of the height and a sensible part of the width.
  EXPECT_GT(b.bottom - b.top, 180);
  EXPECT_GT(b.right - b.left, 100);
  // Shaded, not flat: many grey levels on the face.
  std::vector<int> seen(256, 0);
  for (uint8_t p : g.pixels) seen[p] = 1;
  int levels = 0;
  for (int s : seen) levels += s;
  EXPECT_GT(levels, 60);
}

TEST(ViewerHeadless, SurprisePeakMovesTheForeheadAndNotTheChin) {
  REQUIRE_XVFB();
  const GrayImage neutral = Screenshot({Head()}, "neutral");
  // surprise.clip.json holds Surprise at weight 1 from 0.6 s to 1.7 s.
  const GrayImage peak = Screenshot({Head(), "--clip", Clip("surprise"), "--time", "1.0"}, "peak");
  ASSERT_EQ(neutral.pixels.size(), peak.pixels.size());
  const Box b = Silhouette(neutral);
  const int h = b.bottom - b.top;
  // The forehead: 15-35% down the silhouette; the chin: its last 15%.
  const double forehead = MeanDifference(neutral, peak, b.top + h * 15 / 100, b.top + h * 35 / 100,
                                         b.left, b.right);
  const double chin = MeanDifference(neutral, peak, b.top + h * 85 / 100, b.bottom, b.left, b.right);
  EXPECT_GT(forehead, 2.0) << "forehead " << forehead << ", chin " << chin;
  EXPECT_LT(chin, 0.5) << "forehead " << forehead << ", chin " << chin;
}

TEST(ViewerHeadless, OverlayScreenshotDiffersFromTheShadedOne) {
  REQUIRE_XVFB();
  const std::vector<std::string> pose = {Head(), "--set", "frontalis_inner=1", "--set",
                                         "frontalis_major=1"};
  const GrayImage shaded = Screenshot(pose, "shaded");
  std::vector<std::string> with_overlay = pose;
  with_overlay.insert(with_overlay.end(), {"--overlay", "displacement"});
  const GrayImage overlay = Screenshot(with_overlay, "overlay");
  const Box b = Silhouette(shaded);
  EXPECT_GT(MeanDifference(shaded, overlay, b.top, b.bottom, b.left, b.right), 10.0);
  // The background is the same.
  EXPECT_EQ(shaded.pixels[0], overlay.pixels[0]);
}

TEST(ViewerHeadless, PanelsDrawIntoTheScreenshot) {
  REQUIRE_XVFB();
  // The small test surface, every panel, an overlay: the panels cover the top-left corner.
  const std::string surface = test::SourceDir() + "/assets/surface/surface.rig.json";
  const GrayImage plain = Screenshot({surface, "--overlay", "area-ratio"}, "plain");
  const GrayImage ui = Screenshot({surface, "--overlay", "area-ratio", "--ui"}, "ui");
  EXPECT_GT(MeanDifference(plain, ui, 0, 100, 0, 200), 5.0);
}

// A script's rig edit is rebuilt and swapped into the window before its screenshot: the image
// is the one the saved, edited rig gives when loaded, and not the original rig's.
TEST(ViewerHeadless, AScriptsRigEditIsDrawnAsTheSavedRigDraws) {
  REQUIRE_XVFB();
  const std::string dir = test::TempDir() + "/headless_rig_edit";
  std::filesystem::create_directories(dir);
  const std::string script = dir + "/edit.txt", edited = dir + "/edited.rig.json",
                    shot = dir + "/scripted.png";
  {
    FILE* f = std::fopen(script.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fprintf(f, "set zygomaticus_major 1\nmuscle zygomaticus_major_L strength 25\n"
                    "muscle zygomaticus_major_R strength 25\nsave-rig %s\nscreenshot %s\n",
                 edited.c_str(), shot.c_str());
    std::fclose(f);
  }
  const test::ToolResult r = RunViewer({Head(), "--script", script, "--size", "640x360"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  GrayImage scripted;
  Diagnostics diag;
  ASSERT_TRUE(LoadGrayImage(shot, "test", "screenshot", &scripted, &diag)) << diag.Format();
  const GrayImage reloaded = Screenshot({edited, "--set", "zygomaticus_major=1"}, "reloaded");
  const GrayImage original = Screenshot({Head(), "--set", "zygomaticus_major=1"}, "original");
  ASSERT_EQ(scripted.pixels.size(), reloaded.pixels.size());
  EXPECT_TRUE(scripted.pixels == reloaded.pixels);
  const Box b = Silhouette(original);
  EXPECT_GT(MeanDifference(original, scripted, b.top, b.bottom, b.left, b.right), 0.05);
}

TEST(ViewerHeadless, ABrokenRigExits1WithItsMessages) {
  REQUIRE_XVFB();
  const std::string bad = test::SourceDir() + "/tests/data/bad/rig_mesh_missing.json";
  const std::string out = test::TempDir() + "/never.png";
  const test::ToolResult r = RunViewer({bad, "--screenshot", out});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("rig_mesh_missing.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no screenshot was written"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  // A clip that does not build on the rig: exit 1 naming the clip's problem.
  const test::ToolResult c = RunViewer({test::SourceDir() + "/assets/surface/surface.rig.json",
                                        "--clip", test::SourceDir() + "/tests/data/bad/clip_unknown_muscle.clip.json",
                                        "--screenshot", out});
  EXPECT_EQ(c.exit_code, 1) << c.output;
  EXPECT_NE(c.output.find("zygomatc"), std::string::npos) << c.output;
}

// --egl, and every headless run without DISPLAY, makes the context through EGL: no X server,
// no window. On Mesa both ways rasterise with llvmpipe, the same shaders on the same mesh, so
// the image must be the window's pixel for pixel; with --ui the panels draw too (ImGui without
// its GLFW backend).
TEST(ViewerHeadless, EglWithoutADisplayDrawsWhatTheWindowDraws) {
  REQUIRE_XVFB();
  for (const bool ui : {false, true}) {
    std::vector<std::string> args = {Head(), "--set", "frontalis_major=1", "--overlay",
                                     "displacement"};
    if (ui) args.push_back("--ui");
    const std::string name = ui ? "egl_ui" : "egl";
    const GrayImage window = Screenshot(args, name + "_window");
    const std::string out = test::TempDir() + "/" + name + ".png";
    args.insert(args.end(), {"--egl", "--screenshot", out, "--size", "640x360"});
    const test::ToolResult r = test::RunCommand(
        "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 env -u DISPLAY " +
            test::ShellQuote(MIMETIC_VIEWER_PATH),
        args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    GrayImage egl;
    Diagnostics diag;
    ASSERT_TRUE(LoadGrayImage(out, "test", "screenshot", &egl, &diag)) << diag.Format();
    ASSERT_EQ(egl.width, window.width);
    ASSERT_EQ(egl.height, window.height);
    // The Stats panel (at the bottom, from row 320 on) prints each run's own timings.
    const int rows = ui ? 300 : egl.height;
    int worst = 0;
    for (size_t i = 0; i < size_t(rows) * egl.width; ++i)
      worst = std::max(worst, std::abs(int(egl.pixels[i]) - int(window.pixels[i])));
    EXPECT_LE(worst, 1) << (ui ? "with the panels" : "the face alone");
    // And it is a picture: the head fills a good part of it.
    const Box b = Silhouette(egl);
    EXPECT_GT(b.bottom - b.top, 180);
  }
}

// With no EGL driver to be found (glvnd pointed at a vendor file that does not exist), a
// headless run without a display exits 1 naming what it could not do; nothing is written.
TEST(ViewerHeadless, NoEglDriverExits1WithTheReason) {
  const std::string out = test::TempDir() + "/no_egl.png";
  const test::ToolResult r = test::RunCommand(
      "env -u DISPLAY __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json " +
          test::ShellQuote(MIMETIC_VIEWER_PATH),
      {test::SourceDir() + "/assets/surface/surface.rig.json", "--screenshot", out, "--egl"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot make an OpenGL 3.3 core context through EGL"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(ViewerHeadless, UsageErrorsExit2) {
  const test::ToolResult r = test::RunCommand(test::ShellQuote(MIMETIC_VIEWER_PATH),
                                              {"--overlay", "bogus", "--screenshot", "o.png", "r"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--overlay bogus"), std::string::npos) << r.output;
  // --egl makes a headless run's context; the window has its display.
  const test::ToolResult e = test::RunCommand(test::ShellQuote(MIMETIC_VIEWER_PATH), {"r", "--egl"});
  EXPECT_EQ(e.exit_code, 2) << e.output;
  EXPECT_NE(e.output.find("--egl makes a headless run's context"), std::string::npos) << e.output;
  const test::ToolResult h = test::RunCommand(test::ShellQuote(MIMETIC_VIEWER_PATH), {"--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.output.find("usage: mimetic-viewer"), std::string::npos);
}

TEST(ViewerHeadless, AMissingRigOpensTheWindowInsteadOfExiting) {
  REQUIRE_XVFB();
  // Interactive: the window opens with the message in its Messages panel; `timeout` stops it
  // after 3 s (exit 124: it was still running).
  const test::ToolResult r = test::RunCommand(
      "ASAN_OPTIONS=detect_leaks=0 timeout -s INT -k 5 4 xvfb-run -a " + test::ShellQuote(MIMETIC_VIEWER_PATH),
      {test::TempDir() + "/no_such.rig.json"});
  EXPECT_EQ(r.exit_code, 124) << r.output;
}

// --script end to end (docs/viewer.md "Scripts"): the viewer binary under xvfb-run replays a
// script's edits, saves the clip and takes a screenshot; what it saved reloads with the keys the
// script wrote, the undone edit absent.
std::string Surface() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }

std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(ViewerHeadless, AScriptEditsSavesAndScreenshotsAClip) {
  REQUIRE_XVFB();
  const std::string dir = test::TempDir();
  const std::string clip = dir + "/scripted.clip.json", shot = dir + "/scripted.png";
  const std::string script = WriteText(dir + "/edit.txt",
      "# a clip from nothing\n"
      "clip new " + clip + "\n"
      "key add muscle:zygomatic 0 0 linear\n"
      "key add muscle:zygomatic 1 0.8 cubic\n"
      "key add muscle:frontalis 0.5 0.25 step\n"
      "key move muscle:zygomatic 1 1.5 0.6\n"
      "undo\n"                       // the move is undone: the key is back at (1, 0.8)
      "key delete muscle:frontalis 0.5\n"
      "undo\n"                       // the delete is undone: frontalis keeps its key
      "time 1\n"
      "save-clip\n"
      "screenshot " + shot + "\n");
  const test::ToolResult r = RunViewer({Surface(), "--script", script, "--size", "320x200"});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  ClipSpec saved;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(clip, &saved, &diag)) << diag.Format();
  ASSERT_EQ(saved.channels.size(), 2u);
  const ClipChannelSpec* zyg = nullptr;
  const ClipChannelSpec* fro = nullptr;
  for (const ClipChannelSpec& c : saved.channels) (c.target == "zygomatic" ? zyg : fro) = &c;
  ASSERT_TRUE(zyg && fro);
  ASSERT_EQ(zyg->keys.size(), 2u);
  EXPECT_EQ(zyg->keys[0].t, 0.f);
  EXPECT_EQ(zyg->keys[0].v, 0.f);
  EXPECT_EQ(zyg->keys[0].interp, KeyInterp::kLinear);
  EXPECT_EQ(zyg->keys[1].t, 1.f);
  EXPECT_EQ(zyg->keys[1].v, 0.8f);
  EXPECT_EQ(zyg->keys[1].interp, KeyInterp::kCubic);
  EXPECT_EQ(fro->target, "frontalis");
  ASSERT_EQ(fro->keys.size(), 1u);
  EXPECT_EQ(fro->keys[0].t, 0.5f);
  EXPECT_EQ(fro->keys[0].v, 0.25f);
  EXPECT_EQ(fro->keys[0].interp, KeyInterp::kStep);

  GrayImage g;
  ASSERT_TRUE(LoadGrayImage(shot, "test", "screenshot", &g, &diag)) << diag.Format();
  EXPECT_EQ(g.width, 320);
  EXPECT_EQ(g.height, 200);
  const Box b = Silhouette(g);
  EXPECT_GT(b.bottom - b.top, 50) << "the screenshot shows no surface";
}

TEST(ViewerHeadless, AScriptStopsAtItsFirstBadLineKeepingEarlierSaves) {
  REQUIRE_XVFB();
  const std::string dir = test::TempDir();
  const std::string clip = dir + "/stopped.clip.json";
  const std::string script = WriteText(dir + "/bad_edit.txt",
      "clip new " + clip + "\n"
      "key add muscle:zygomatic 0 0.5\n"
      "save-clip\n"
      "key add muscle:zygomatic 1 1.5\n"   // line 4: a value outside [0, 1]
      "key add muscle:zygomatic 2 0.1\n"
      "save-clip\n");
  const test::ToolResult r = RunViewer({Surface(), "--script", script});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad_edit.txt:4:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1.5"), std::string::npos) << r.output;
  ClipSpec saved;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(clip, &saved, &diag)) << diag.Format();
  ASSERT_EQ(saved.channels.size(), 1u);
  ASSERT_EQ(saved.channels[0].keys.size(), 1u);  // line 5 never ran
  EXPECT_EQ(saved.channels[0].keys[0].v, 0.5f);
}

// A viewer killed in the middle of a save (MIMETIC_TEST_EXIT_BEFORE_RENAME ends it after the
// temporary file is written and before the rename, exit 86) leaves the old file byte for byte;
// the same script without the fault then replaces it.
TEST(ViewerHeadless, AViewerKilledDuringASaveLeavesTheOldFile) {
  REQUIRE_XVFB();
  const std::string dir = test::TempDir();
  const std::string clip = dir + "/take.clip.json";
  const std::string old_text =
      "{\"format\": \"mimetic-clip\", \"version\": 1, \"name\": \"take\", \"channels\": ["
      "{\"muscle\": \"zygomatic\", \"keys\": [{\"t\": 0, \"v\": 0.25}]}]}\n";
  WriteText(clip, old_text);
  {  // the file is a valid clip to begin with
    ClipSpec spec;
    Diagnostics diag;
    ASSERT_TRUE(LoadClip(clip, &spec, &diag)) << diag.Format();
  }
  const std::string script = WriteText(dir + "/edit.txt",
      "load-clip " + clip + "\n"
      "key add muscle:zygomatic 1 0.75\n"
      "save-clip\n");
  const test::ToolResult killed = test::RunCommand(
      "MIMETIC_TEST_EXIT_BEFORE_RENAME=take.clip.json " + std::string(kViewer) +
          test::ShellQuote(MIMETIC_VIEWER_PATH),
      {Surface(), "--script", script});
  EXPECT_EQ(killed.exit_code, 86) << killed.output;
  EXPECT_EQ(test::ReadFileBytes(clip), old_text) << "the killed save changed the old file";

  const test::ToolResult ok = RunViewer({Surface(), "--script", script});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  ClipSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(clip, &spec, &diag)) << diag.Format();
  ASSERT_EQ(spec.channels.size(), 1u);
  ASSERT_EQ(spec.channels[0].keys.size(), 2u);
  EXPECT_EQ(spec.channels[0].keys[0].v, 0.25f);
  EXPECT_EQ(spec.channels[0].keys[1].t, 1.f);
  EXPECT_EQ(spec.channels[0].keys[1].v, 0.75f);
}

// Fine scale (docs/viewer.md "Fine scale"): the shader bump-maps the slopes of the two height
// maps. Maps written here: a flat map has no slope, so at any depth the image is the plain one,
// bit for bit, as it is at depth 0 with furrowed maps; furrows (stripes across v, on the head's
// cylindrical uv: horizontal lines) change the shading of the face.
std::string WriteFineMaps(const std::string& dir, bool stripes) {
  for (int k = 1; k <= 2; ++k) {
    Gray16Image m;
    m.width = m.height = 256;
    m.pixels.assign(size_t(m.width) * m.height, 65535);
    if (stripes)
      for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x)
          m.pixels[size_t(y) * m.width + x] =
              uint16_t(32768 + 32767 * std::cos(2.0 * M_PI * (y * (k == 1 ? 24.0 : 0.0)) / m.height));
    Diagnostics diag;
    EXPECT_TRUE(SavePng16(dir + "/fine_height_" + std::to_string(k) + ".png", m, &diag)) << diag.Format();
  }
  return dir;
}

TEST(ViewerHeadless, FineMapsBumpTheShadingByTheirSlopesOnly) {
  REQUIRE_XVFB();
  const std::string flat = test::TempDir(), furrowed = test::TempDir();
  WriteFineMaps(flat, false);
  WriteFineMaps(furrowed, true);
  const std::vector<std::string> pose = {Head(), "--set", "frontalis_inner=1"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> all = pose;
    all.insert(all.end(), extra.begin(), extra.end());
    return all;
  };
  const GrayImage plain = Screenshot(pose, "fine_plain");
  const GrayImage flat_deep = Screenshot(with({"--fine", flat, "--fine-depth", "5"}), "fine_flat");
  const GrayImage zero = Screenshot(with({"--fine", furrowed, "--fine-depth", "0"}), "fine_zero");
  const GrayImage bumped = Screenshot(with({"--fine", furrowed, "--fine-depth", "0.5"}), "fine_bumped");
  ASSERT_EQ(plain.pixels.size(), bumped.pixels.size());
  EXPECT_EQ(flat_deep.pixels, plain.pixels) << "a map without slope changed the shading";
  EXPECT_EQ(zero.pixels, plain.pixels) << "depth 0 changed the shading";
  const Box b = Silhouette(plain);
  EXPECT_GT(MeanDifference(plain, bumped, b.top, b.bottom, b.left, b.right), 1.0);
  EXPECT_EQ(plain.pixels[0], bumped.pixels[0]);  // the background is not bumped
}

TEST(ViewerHeadless, MissingFineMapsExit1NamingTheFile) {
  REQUIRE_XVFB();
  const std::string dir = test::TempDir(), out = dir + "/never.png";
  const test::ToolResult r = RunViewer({Head(), "--fine", dir, "--screenshot", out});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(dir + "/fine_height_1.png"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("mimetic texture"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace mimetic::viewer

namespace mimetic::viewer {
namespace {

// The rig's mesh file's other meshes are drawn beside the skin (the sample head's eyeballs,
// docs/viewer.md): the same rig on a copy of its glb without the eyes mesh draws the same
// skin, so the two frames differ only where the eyes are, and they do differ there (in the
// upper middle of the face, the eye line), nowhere near the chin.
TEST(ViewerHeadless, TheMeshFilesEyeballsAreDrawnBesideTheSkin) {
  REQUIRE_XVFB();
  const std::string dir = test::TempDir();
  MeshData skin;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(test::SourceDir() + "/assets/head/sample_head.glb", "", &skin, &diag))
      << diag.Format();
  ASSERT_TRUE(ExportMesh(dir + "/skin_only.glb", skin, &diag)) << diag.Format();
  const std::string skin_only = test::EditedSampleRig("skin_only", [&](nlohmann::json& j) {
    j["mesh"] = {{"path", dir + "/skin_only.glb"}};
  });
  const GrayImage with = Screenshot({Head()}, "with_eyes");
  const GrayImage without = Screenshot({skin_only}, "without_eyes");
  ASSERT_EQ(with.pixels.size(), without.pixels.size());
  const Box b = Silhouette(with);
  const int h = b.bottom - b.top;
  // The eye line: 40-50% of the head's height from the crown in this front view.
  const int eyes0 = b.top + int(0.40 * h), eyes1 = b.top + int(0.52 * h);
  EXPECT_GT(MeanDifference(with, without, eyes0, eyes1, b.left, b.right), 0.5);
  EXPECT_EQ(MeanDifference(with, without, b.top + int(0.8 * h), b.bottom, b.left, b.right), 0.0);
}

}  // namespace
}  // namespace mimetic::viewer
