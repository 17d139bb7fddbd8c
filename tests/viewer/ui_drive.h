// tests/viewer/ui_drive.h: drives the real, windowed mimetic-viewer with synthetic X input
// (docs/viewer.md "Tested by driving the UI"). UiDriver starts
//   xvfb-run -a -s "-screen 0 1600x950x24" mimetic-viewer ARGS --ui-trace TRACE
// in its own process group, learns the DISPLAY xvfb-run chose, waits for the first frames, then
// moves, clicks, drags and types with xdotool on that display. Where to click comes from the
// viewer's --ui-trace file (the screen rectangles of the widgets the tests drive, rewritten
// after every frame), never from hard-coded pixels; every step waits for frames to pass so ImGui
// sees it. Every wait has a timeout; Stop (and the destructor) ends the whole process group.
// A failed step records a gtest failure with the viewer's output and returns false.
#pragma once

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace mimetic::viewer::uidrive {

inline bool HaveCommand(const char* name) {
  return std::system((std::string("command -v ") + name + " >/dev/null 2>&1").c_str()) == 0;
}

// Skips (fails under CI, which installs both: tools/install-deps.sh) without xvfb-run or xdotool.
#define REQUIRE_XVFB_AND_XDOTOOL()                                                                 \
  do {                                                                                             \
    for (const char* tool : {"xvfb-run", "xdotool"}) {                                             \
      if (!::mimetic::viewer::uidrive::HaveCommand(tool)) {                                        \
        if (std::getenv("CI")) FAIL() << tool << " is missing (bash tools/install-deps.sh)";       \
        GTEST_SKIP() << tool << " is missing (bash tools/install-deps.sh installs it); the UI "    \
                        "is not driven";                                                           \
      }                                                                                            \
    }                                                                                              \
  } while (0)

struct Rect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float cx() const { return 0.5f * (x0 + x1); }
  float cy() const { return 0.5f * (y0 + y1); }
};

class UiDriver {
 public:
  static constexpr int kWidth = 1600, kHeight = 950;  // the viewer's window (viewer/app/main.cpp)

  ~UiDriver() { Stop(); }

  // Starts the viewer with `args` (the rig and options; --ui-trace is added) and waits (60 s at
  // most: the sanitizer build loads slowly) for its third frame. xvfb-run itself fails now and
  // then when tests run in parallel (it prints "xvfb-run: error", as in headless_test.cpp): such
  // a start is tried again, twice at most.
  bool Start(const std::vector<std::string>& args) {
    for (int attempt = 0; attempt < 3; ++attempt) {
      const int started = StartOnce(args);
      if (started >= 0) return started == 1;
      Stop();
    }
    ADD_FAILURE() << "xvfb-run failed three times\n" << Log();
    return false;
  }

  // Ends the process group (SIGTERM, then SIGKILL after 10 s); the files a test saved before are
  // complete (the viewer writes them atomically).
  void Stop() {
    if (pid_ <= 0) return;
    kill(-pid_, SIGTERM);
    int status = 0;
    bool done = WaitFor([&] { return waitpid(pid_, &status, WNOHANG) == pid_; }, 10.0);
    if (!done) {
      kill(-pid_, SIGKILL);
      waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }

  // Waits (`seconds` at most) for the viewer to end by itself (xvfb-run passes its exit status
  // on): true with the exit code (-1: killed by a signal); false, a failure recorded, when it
  // still runs (Stop then ends it).
  bool WaitExit(double seconds, int* code) {
    int status = 0;
    if (pid_ <= 0 || !WaitFor([&] { return waitpid(pid_, &status, WNOHANG) == pid_; }, seconds)) {
      ADD_FAILURE() << "the viewer did not exit within " << seconds << " s\n" << Log();
      return false;
    }
    pid_ = -1;
    *code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return true;
  }

  std::string Log() const { return "viewer output:\n" + test::ReadFileBytes(log_); }
  const std::string& dir() const { return dir_; }
  const nlohmann::json& trace() const { return trace_json_; }
  uint64_t frame() const { return frame_; }

  // Waits (10 s at most) until `n` more frames were drawn; the trace is then that frame's.
  bool Frames(int n = 3) {
    const uint64_t until = frame_ + uint64_t(n);
    if (WaitFor([&] { return ReadTrace() && frame_ >= until; }, 10.0)) return true;
    ADD_FAILURE() << "the viewer stopped drawing frames (at frame " << frame_ << ")\n" << Log();
    return false;
  }

  bool Has(const std::string& name) const { return trace_json_["items"].contains(name); }
  // The rectangle of a traced widget, in the X screen's pixels (the window's origin added).
  Rect Item(const std::string& name) const {
    Rect r;
    const nlohmann::json& items = trace_json_["items"];
    if (!items.contains(name)) {
      ADD_FAILURE() << "the UI trace has no widget '" << name << "'; it has: " << items.dump();
      return r;
    }
    const nlohmann::json& a = items[name];
    const float wx = trace_json_["window"][0].get<float>(), wy = trace_json_["window"][1].get<float>();
    r.x0 = a[0].get<float>() + wx, r.y0 = a[1].get<float>() + wy;
    r.x1 = a[2].get<float>() + wx, r.y1 = a[3].get<float>() + wy;
    return r;
  }
  double Value(const std::string& name) const {
    const nlohmann::json& values = trace_json_["values"];
    if (!values.contains(name)) {
      ADD_FAILURE() << "the UI trace has no value '" << name << "'";
      return 0.0;
    }
    return values[name].get<double>();
  }

  // One xdotool command line on the viewer's display (10 s at most), then `frames` frames
  // counted from the trace read after xdotool returned: the first of them may have polled its
  // events before the input arrived, the second started after it, so 2 frames see it handled.
  bool Xdo(const std::string& commands, int frames = 2) {
    const std::string line = "DISPLAY=" + test::ShellQuote(display_) + " XAUTHORITY=" +
                             test::ShellQuote(xauthority_) + " timeout 10 xdotool " + commands + " 2>&1";
    const int rc = std::system(line.c_str());
    if (rc != 0) {
      ADD_FAILURE() << "xdotool " << commands << " failed (" << rc << ")\n" << Log();
      return false;
    }
    ReadTrace();
    return Frames(frames);
  }
  bool MoveTo(int x, int y) { return Xdo("mousemove " + std::to_string(x) + " " + std::to_string(y)); }
  // A left click at (x, y): the pointer moves there first, so ImGui sees the hover, then the
  // button goes down and up on separate frames.
  bool Click(int x, int y) { return MoveTo(x, y) && Xdo("mousedown 1") && Xdo("mouseup 1"); }
  // A click on a traced widget. The layout can move between frames (a status line appears
  // above the widget, a rebuild's progress): the pointer is moved again until the widget is
  // under it on the frame before the press (5 tries), and the button goes up on it too.
  bool ClickItem(const std::string& name) {
    for (int attempt = 0; attempt < 5; ++attempt) {
      if (!Has(name)) break;
      Rect r = Item(name);
      const int x = int(r.cx()), y = int(r.cy());
      if (!MoveTo(x, y)) return false;
      if (!Has(name)) break;
      r = Item(name);
      if (x < r.x0 || x >= r.x1 || y < r.y0 || y >= r.y1) continue;  // it moved: aim again
      return Xdo("mousedown 1") && Xdo("mouseup 1");
    }
    ADD_FAILURE() << "cannot click '" << name << "': it is not in the UI trace or keeps moving; items: "
                  << trace_json_["items"].dump();
    return false;
  }
  // Ctrl + left click: on an ImGui slider, a text field to type the exact value into.
  bool CtrlClick(int x, int y) {
    return MoveTo(x, y) && Xdo("keydown ctrl") && Xdo("mousedown 1") && Xdo("mouseup 1") && Xdo("keyup ctrl");
  }
  // A left drag from (x0, y0) to (x1, y1) in `steps` moves, a frame or more each.
  bool Drag(int x0, int y0, int x1, int y1, int steps = 2) {
    if (!MoveTo(x0, y0) || !Xdo("mousedown 1")) return false;
    for (int i = 1; i <= steps; ++i)
      if (!MoveTo(x0 + (x1 - x0) * i / steps, y0 + (y1 - y0) * i / steps)) return false;
    return Xdo("mouseup 1");
  }
  bool Type(const std::string& text) { return Xdo("type --delay 30 " + test::ShellQuote(text)); }
  // Keys down and up on separate frames (ImGui 1.86 reads key state once a frame: a press and
  // release within one frame would be missed), e.g. "ctrl+z" or "Return".
  // Each key of a chord goes down on its own frames, and up in reverse order.
  bool Key(const std::string& keys) {
    std::vector<std::string> chord;
    for (size_t at = 0; at <= keys.size();) {
      const size_t plus = std::min(keys.find('+', at), keys.size());
      chord.push_back(keys.substr(at, plus - at));
      at = plus + 1;
    }
    for (const std::string& k : chord)
      if (!Xdo("keydown " + k)) return false;
    for (size_t i = chord.size(); i-- > 0;)
      if (!Xdo("keyup " + chord[i])) return false;
    return true;
  }

 private:
  // 1 started, 0 the viewer failed (a gtest failure is recorded), -1 xvfb-run failed.
  int StartOnce(const std::vector<std::string>& args) {
    dir_ = test::TempDir();
    trace_ = dir_ + "/trace.json";
    log_ = dir_ + "/viewer.log";
    const std::string display_file = dir_ + "/display";
    std::string viewer = test::ShellQuote(MIMETIC_VIEWER_PATH);
    for (const std::string& a : args) viewer += " " + test::ShellQuote(a);
    viewer += " --ui-trace " + test::ShellQuote(trace_) + " --autosave-seconds 0";
    // xvfb-run's display and the cookie file it made (xdotool needs both).
    const std::string inner = "printf '%s\\n%s\\n' \"$DISPLAY\" \"$XAUTHORITY\" > " + test::ShellQuote(display_file) + "; exec " + viewer;
    const std::string command = "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 exec xvfb-run -a -s '-screen 0 " +
                                std::to_string(kWidth) + "x" + std::to_string(kHeight) + "x24' sh -c " +
                                test::ShellQuote(inner) + " > " + test::ShellQuote(log_) + " 2>&1";
    pid_ = fork();
    if (pid_ < 0) {
      ADD_FAILURE() << "fork failed";
      return 0;
    }
    if (pid_ == 0) {
      setsid();  // its own process group: Stop ends xvfb-run, Xvfb and the viewer together
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    bool exited = false;
    const bool up = WaitFor([&] {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {  // gone before its first frames
        exited = true;
        pid_ = -1;
        return true;
      }
      const std::string text = test::ReadFileBytes(display_file);
      const size_t nl = text.find('\n');
      if (nl == std::string::npos || text.back() != '\n') return false;
      display_ = text.substr(0, nl);
      xauthority_ = text.substr(nl + 1, text.size() - nl - 2);
      return !display_.empty() && ReadTrace() && frame_ >= 3;
    }, 60.0);
    if (up && !exited) return 1;
    if (Log().find("xvfb-run: error") != std::string::npos) return -1;
    ADD_FAILURE() << (exited ? "the viewer exited before its first frames"
                             : "the viewer showed no frame within 60 s")
                  << " (display '" << display_ << "')\n" << Log();
    return 0;
  }

  template <typename F>
  static bool WaitFor(F done, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!done()) {
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  bool ReadTrace() {
    const std::string text = test::ReadFileBytes(trace_);
    if (text.empty()) return false;
    nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.contains("frame")) return false;
    trace_json_ = std::move(j);
    frame_ = trace_json_["frame"].get<uint64_t>();
    return true;
  }

  pid_t pid_ = -1;
  std::string dir_, trace_, log_, display_, xauthority_;
  nlohmann::json trace_json_;
  uint64_t frame_ = 0;
};

}  // namespace mimetic::viewer::uidrive
