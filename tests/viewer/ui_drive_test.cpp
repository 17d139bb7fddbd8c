// The real, windowed viewer driven with the mouse and the keyboard (tests/viewer/ui_drive.h,
// docs/viewer.md "Tested by driving the UI"): widgets are found through --ui-trace, the input is
// synthetic X input (xdotool) under Xvfb, and what is checked is what the viewer saved.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "tests/viewer/ui_drive.h"

namespace mimetic::viewer {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using uidrive::Rect;
using uidrive::UiDriver;

json ReadJson(const std::string& path) {
  const std::string text = test::ReadFileBytes(path);
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  EXPECT_FALSE(text.empty() || j.is_discarded()) << path << " is not JSON:\n" << text;
  return j;
}

// The small test surface copied into `dir` with an empty library beside it.
struct SurfaceFiles {
  std::string rig, library;
};
SurfaceFiles CopySurface(const std::string& dir) {
  fs::copy(test::SourceDir() + "/assets/surface", dir + "/surface");
  SurfaceFiles f{dir + "/surface/surface.rig.json", dir + "/ui.library.json"};
  std::ofstream(f.library) << R"({"format": "mimetic-expression-library", "version": 1, "expressions": []})";
  return f;
}

const json* FindExpression(const json& library, const std::string& name) {
  for (const json& e : library["expressions"])
    if (e["name"] == name) return &e;
  return nullptr;
}

// The top muscle slider of the Muscles panel (its frame, without the label): name and rectangle.
std::string FirstMuscle(const UiDriver& ui, Rect* rect) {
  std::string best;
  float best_y = 1e9f;
  for (const auto& [name, r] : ui.trace()["items"].items())
    if (name.rfind("muscle/", 0) == 0 && r[1].get<float>() < best_y) best = name, best_y = r[1].get<float>();
  if (best.empty()) {
    ADD_FAILURE() << "no muscle slider in the UI trace";
    return "";
  }
  *rect = ui.Item(best);
  return best.substr(7);
}

// Ctrl+click the top muscle slider, type `value`, Enter; name the pose in the Expressions
// panel and "Save pose as"; the pointer then rests over the 3D view. *muscle gets the slider's.
void SavePoseAs(UiDriver& ui, const std::string& name, const std::string& value = "0.5",
                std::string* muscle = nullptr) {
  Rect slider;
  const std::string m = FirstMuscle(ui, &slider);
  ASSERT_FALSE(m.empty());
  if (muscle) *muscle = m;
  ASSERT_TRUE(ui.CtrlClick(int(slider.cx()), int(slider.cy())));
  ASSERT_TRUE(ui.Key("ctrl+a"));
  ASSERT_TRUE(ui.Type(value));
  ASSERT_TRUE(ui.Key("Return"));
  ASSERT_TRUE(ui.ClickItem("expr/name"));
  ASSERT_TRUE(ui.Type(name));
  ASSERT_TRUE(ui.ClickItem("expr/save-pose-as"));
  ASSERT_TRUE(ui.MoveTo(UiDriver::kWidth / 2, UiDriver::kHeight / 2));
}

// Ctrl+click on a muscle slider, type a value, Enter; name the pose in the Expressions panel,
// "Save pose as", "Save library": the library file holds the new expression with exactly that
// activation (and no other muscle active), beside the expressions it had.
TEST(ViewerUiDrive, TypingASliderValueAndSavingThePoseWritesTheExpression) {
  REQUIRE_XVFB_AND_XDOTOOL();
  const std::string dir = test::TempDir();
  const SurfaceFiles files = CopySurface(dir);
  const size_t before = ReadJson(files.library)["expressions"].size();
  UiDriver ui;
  ASSERT_TRUE(ui.Start({files.rig, "--library", files.library}));
  std::string muscle;
  SavePoseAs(ui, "ui_typed", "0.37", &muscle);
  ASSERT_FALSE(muscle.empty());
  ASSERT_TRUE(ui.ClickItem("files/save-library"));
  ui.Stop();
  const json library = ReadJson(files.library);
  ASSERT_EQ(library["expressions"].size(), before + 1) << library.dump(1) << "\n" << ui.Log();
  const json* e = FindExpression(library, "ui_typed");
  ASSERT_NE(e, nullptr) << library.dump(1);
  ASSERT_TRUE((*e)["activations"].contains(muscle)) << e->dump();
  EXPECT_NEAR((*e)["activations"][muscle].get<double>(), 0.37, 1e-6) << e->dump();
  for (const auto& [name, value] : (*e)["activations"].items()) {
    if (name == muscle) continue;
    EXPECT_EQ(value.get<double>(), 0.0) << name << " in " << e->dump();
  }
}

// A drag on a muscle slider sets the value the pointer's position along the slider gives
// (ImGui's SliderFloat: the grab's centre follows the pointer over the width less the grab),
// and Ctrl+Z (docs/viewer.md "Shortcuts": undo the last edit) takes back the saved expression:
// Save library after it writes the library without it.
TEST(ViewerUiDrive, DraggingASliderThenCtrlZUndoesTheSavedExpression) {
  REQUIRE_XVFB_AND_XDOTOOL();
  const std::string dir = test::TempDir();
  const SurfaceFiles files = CopySurface(dir);
  UiDriver ui;
  ASSERT_TRUE(ui.Start({files.rig, "--library", files.library}));
  Rect slider;
  const std::string muscle = FirstMuscle(ui, &slider);
  ASSERT_FALSE(muscle.empty());
  // ImGui 1.86 SliderBehavior: a float slider's grab is GrabMinSize wide (10 px in the default
  // style) and its centre moves over the frame less 2 px of grab padding at each end, so the
  // value is (x - (x0 + 2 + 5)) / ((x1 - 2 - 5) - (x0 + 2 + 5)), rounded to the "%.3f" format.
  const float lo = slider.x0 + 2.f + 5.f, hi = slider.x1 - 2.f - 5.f;
  const int target_x = int(std::lround(lo + 0.25f * (hi - lo)));
  const double expected = (target_x - lo) / (hi - lo);
  ASSERT_TRUE(ui.Drag(int(slider.x1) - 3, int(slider.cy()), target_x, int(slider.cy())));
  ASSERT_TRUE(ui.ClickItem("expr/name"));
  ASSERT_TRUE(ui.Type("ui_dragged"));
  ASSERT_TRUE(ui.ClickItem("expr/save-pose-as"));
  ASSERT_TRUE(ui.ClickItem("files/save-library"));
  ASSERT_TRUE(ui.Frames());
  const json saved = ReadJson(files.library);
  const json* e = FindExpression(saved, "ui_dragged");
  ASSERT_NE(e, nullptr) << saved.dump(1) << "\n" << ui.Log();
  ASSERT_TRUE((*e)["activations"].contains(muscle)) << e->dump();
  // Within a pixel's worth of the slider.
  EXPECT_NEAR((*e)["activations"][muscle].get<double>(), expected, 1.0 / (hi - lo)) << e->dump();
  // Ctrl+Z with the pointer over the 3D view (no widget has the keyboard), then Save library.
  ASSERT_TRUE(ui.MoveTo(UiDriver::kWidth / 2, UiDriver::kHeight / 2));
  ASSERT_EQ(ui.Value("library/expressions"), double(saved["expressions"].size()));
  ASSERT_TRUE(ui.Key("ctrl+z"));
  EXPECT_EQ(ui.Value("library/expressions"), double(saved["expressions"].size() - 1))
      << "Ctrl+Z did not take the expression back";
  ASSERT_TRUE(ui.ClickItem("files/save-library"));
  ui.Stop();
  const json undone = ReadJson(files.library);
  EXPECT_EQ(FindExpression(undone, "ui_dragged"), nullptr) << undone.dump(1);
  EXPECT_EQ(undone["expressions"].size(), saved["expressions"].size() - 1) << undone.dump(1);
}

// The Scene panel (opened at y = 130) lies over the Files panel's lower part, "Save rig"
// included: a click on the Files panel's title bar (its top 5 px) brings it to the front first.
bool FilesToFront(UiDriver& ui) {
  const Rect w = ui.Item("window/Files");
  return !::testing::Test::HasFatalFailure() && ui.Click(int(w.cx()), int(w.y0) + 5);
}

json CurveControls(const json& rig, const std::string& curve) {
  for (const json& c : rig["curve_wrinkles"])
    if (c["name"] == curve) return c["control"];
  ADD_FAILURE() << "the rig has no curve wrinkle " << curve;
  return json::array();
}

// A control point dragged by (dx, dy) pixels in the UV curve editor, then "Save rig": the saved
// point moved by (dx, dy) / (the editor's pixels per uv), the curve's other points did not;
// Ctrl+Z and "Save rig" again: the point is back where it was.
TEST(ViewerUiDrive, DraggingAUvControlPointMovesItByThePixelsOverTheScale) {
  REQUIRE_XVFB_AND_XDOTOOL();
  const std::string dir = test::TempDir();
  fs::copy(test::SourceDir() + "/assets/head", dir + "/head");
  const std::string rig = dir + "/head/sample_head.rig.json";
  const json original = ReadJson(rig);
  UiDriver ui;
  ASSERT_TRUE(ui.Start({rig, "--panel", "uv-curves"}));
  ASSERT_TRUE(ui.Frames());  // the editor frames the curves on its first frame
  const Rect canvas = ui.Item("uv/canvas");
  const double scale = ui.Value("uv/pixels-per-uv");
  ASSERT_GT(scale, 10.0);
  const int dx = 14, dy = -9;
  // A handle (K = 1 or 2) inside the canvas, 20 px or more from every other point (the editor
  // takes the nearest point within 8 px), whose target is inside the canvas too.
  std::vector<std::pair<std::string, Rect>> points;
  for (const auto& [name, r] : ui.trace()["items"].items())
    if (name.rfind("uv/point/", 0) == 0) points.emplace_back(name, ui.Item(name));
  std::string chosen;
  Rect at;
  for (const auto& [name, r] : points) {
    const char k = name.back();
    if (k != '1' && k != '2') continue;
    const auto inside = [&](float x, float y) {
      return x > canvas.x0 + 20 && x < canvas.x1 - 20 && y > canvas.y0 + 20 && y < canvas.y1 - 20;
    };
    if (!inside(r.x0, r.y0) || !inside(r.x0 + dx, r.y0 + dy)) continue;
    bool alone = true;
    for (const auto& [other, q] : points)
      if (other != name && std::hypot(q.x0 - r.x0, q.y0 - r.y0) < 20.f) alone = false;
    if (alone) {
      chosen = name, at = r;
      break;
    }
  }
  ASSERT_FALSE(chosen.empty()) << "no control point stands alone in the UV view: " << ui.trace()["items"].dump();
  // uv/point/CURVE/K
  const std::string curve = chosen.substr(9, chosen.size() - 11);
  const int k = chosen.back() - '0';
  const int x0 = int(std::lround(at.x0)), y0 = int(std::lround(at.y0));
  ASSERT_TRUE(ui.Drag(x0, y0, x0 + dx, y0 + dy));
  ASSERT_TRUE(FilesToFront(ui));
  ASSERT_TRUE(ui.ClickItem("files/save-rig"));
  const json before = CurveControls(original, curve);
  const json moved = CurveControls(ReadJson(rig), curve);
  ASSERT_EQ(moved.size(), 4u) << moved.dump();
  // The point follows the pointer: the press was at the point rounded to a pixel (half a pixel
  // off at most on each axis), so within 0.6 px of the drag.
  const double tol = 0.6 / scale;
  EXPECT_NEAR(moved[k][0].get<double>(), before[k][0].get<double>() + dx / scale, tol) << curve << " " << k;
  EXPECT_NEAR(moved[k][1].get<double>(), before[k][1].get<double>() + dy / scale, tol) << curve << " " << k;
  for (int j = 0; j < 4; ++j) {
    if (j == k) continue;
    for (int a = 0; a < 2; ++a)
      EXPECT_NEAR(moved[j][a].get<double>(), before[j][a].get<double>(), 1e-6) << curve << " point " << j;
  }
  // Ctrl+Z over the 3D view (the whole drag is one command), then Save rig: back to the start.
  ASSERT_TRUE(ui.MoveTo(UiDriver::kWidth - 200, UiDriver::kHeight / 2));
  ASSERT_TRUE(ui.Key("ctrl+z"));
  ASSERT_TRUE(ui.ClickItem("files/save-rig"));  // the Files panel is still in front
  ui.Stop();
  const json undone = CurveControls(ReadJson(rig), curve);
  for (int j = 0; j < 4; ++j)
    for (int a = 0; a < 2; ++a)
      EXPECT_NEAR(undone[j][a].get<double>(), before[j][a].get<double>(), 1e-6) << curve << " point " << j << "\n" << ui.Log();
}

// A pose saved as an expression leaves the library with unsaved changes. Ctrl+Q (the pointer
// over the 3D view) asks first ("Quit with unsaved changes?"): "Save and quit" ends the viewer
// with exit 0 and the library file holds the expression; "Quit without saving" ends it and
// leaves the file as it was, byte for byte.
TEST(ViewerUiDrive, CtrlQWithUnsavedChangesAsksThenSavesOrQuitsAsAnswered) {
  REQUIRE_XVFB_AND_XDOTOOL();
  for (const bool save : {true, false}) {
    SCOPED_TRACE(save ? "save and quit" : "quit without saving");
    const std::string dir = test::TempDir();
    const SurfaceFiles files = CopySurface(dir);
    const std::string before = test::ReadFileBytes(files.library);
    UiDriver ui;
    ASSERT_TRUE(ui.Start({files.rig, "--library", files.library}));
    SavePoseAs(ui, "ui_quit");
    ASSERT_TRUE(ui.Key("ctrl+q"));
    ASSERT_TRUE(ui.Frames());
    ASSERT_TRUE(ui.Has("quit/save-and-quit")) << "Ctrl+Q with unsaved changes did not ask\n" << ui.Log();
    // The last click: the viewer ends on the frame after the button goes up, so no frames
    // are waited for after it.
    const Rect button = ui.Item(save ? "quit/save-and-quit" : "quit/without-saving");
    ASSERT_TRUE(ui.MoveTo(int(button.cx()), int(button.cy())));
    ASSERT_TRUE(ui.Xdo("mousedown 1"));
    ASSERT_TRUE(ui.Xdo("mouseup 1", 0));
    int code = -2;
    ASSERT_TRUE(ui.WaitExit(20.0, &code));
    EXPECT_EQ(code, 0) << ui.Log();
    if (save) {
      const json library = ReadJson(files.library);
      EXPECT_NE(FindExpression(library, "ui_quit"), nullptr) << library.dump(1);
    } else {
      EXPECT_EQ(test::ReadFileBytes(files.library), before);
    }
  }
}

// Loading the library again with unsaved changes asks first ("Discard unsaved changes?"):
// Cancel keeps the edited library (the new expression is still listed); Discard loads the file,
// which does not have it.
TEST(ViewerUiDrive, LoadingOverUnsavedChangesAsksAndCancelKeepsThem) {
  REQUIRE_XVFB_AND_XDOTOOL();
  const std::string dir = test::TempDir();
  const SurfaceFiles files = CopySurface(dir);
  const size_t on_file = ReadJson(files.library)["expressions"].size();
  UiDriver ui;
  ASSERT_TRUE(ui.Start({files.rig, "--library", files.library}));
  SavePoseAs(ui, "ui_kept");
  ASSERT_EQ(ui.Value("library/expressions"), double(on_file + 1));
  ASSERT_TRUE(FilesToFront(ui));
  ASSERT_TRUE(ui.ClickItem("files/load-library"));
  ASSERT_TRUE(ui.Frames());
  ASSERT_TRUE(ui.Has("discard/cancel")) << "loading over unsaved changes did not ask\n" << ui.Log();
  ASSERT_TRUE(ui.ClickItem("discard/cancel"));
  ASSERT_TRUE(ui.Frames());
  EXPECT_FALSE(ui.Has("discard/cancel"));
  EXPECT_EQ(ui.Value("library/expressions"), double(on_file + 1)) << "Cancel dropped the edit";
  ASSERT_TRUE(ui.ClickItem("files/load-library"));
  ASSERT_TRUE(ui.Frames());
  ASSERT_TRUE(ui.ClickItem("discard/discard"));
  ASSERT_TRUE(ui.Frames());
  EXPECT_EQ(ui.Value("library/expressions"), double(on_file)) << "Discard did not load the file";
  ui.Stop();
}

}  // namespace
}  // namespace mimetic::viewer
