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
  Rect slider;
  const std::string muscle = FirstMuscle(ui, &slider);
  ASSERT_FALSE(muscle.empty());
  ASSERT_TRUE(ui.CtrlClick(int(slider.cx()), int(slider.cy())));
  ASSERT_TRUE(ui.Key("ctrl+a"));
  ASSERT_TRUE(ui.Type("0.37"));
  ASSERT_TRUE(ui.Key("Return"));
  ASSERT_TRUE(ui.ClickItem("expr/name"));
  ASSERT_TRUE(ui.Type("ui_typed"));
  ASSERT_TRUE(ui.ClickItem("expr/save-pose-as"));
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

}  // namespace
}  // namespace mimetic::viewer
