// viewer/app/main.cpp: mimetic-viewer (docs/viewer.md). A window with the panels, or, with
// --screenshot / --bench-frames, one headless run (a hidden window's context, an offscreen
// framebuffer) that exits 0 done, 1 an input failed (every message on stderr), 2 usage.
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/file_util_hook.h"
#include "io/image.h"
#include "viewer/app/app.h"
#include "viewer/app/egl_context.h"
#include "viewer/core/args.h"
#include "viewer/core/script.h"
#include "viewer/core/timeline.h"

namespace mimetic::viewer {
namespace {

constexpr int kExitInput = 1, kExitUsage = 2;

// Fault injection for the tests (tests/viewer/headless_test.cpp): with
// MIMETIC_TEST_EXIT_BEFORE_RENAME=TEXT, an atomic write of a path containing TEXT ends the
// process (exit 86) after its temporary file is written and before the rename.
std::string g_exit_before_rename;
void ExitBeforeRename(const std::string& tmp, const std::string& path) {
  (void)tmp;
  if (path.find(g_exit_before_rename) != std::string::npos) _exit(86);
}

void PrintMessages(const Session& s) {
  for (const Message& m : s.messages())
    std::fprintf(stderr, "%s: %s\n", m.error ? "error" : "warning", m.text.c_str());
}

bool HasErrors(const Session& s) {
  for (const Message& m : s.messages())
    if (m.error) return true;
  return false;
}

// Loads what the command line names. Headless: false on any error (the caller exits 1).
// Interactive: every problem stays in the Messages panel.
bool LoadInputs(const ViewerArgs& args, App* app) {
  Session& s = app->session;
  if (!args.rig.empty() && s.LoadRigFile(args.rig)) app->OnRigLoaded();
  s.fine_depth = args.fine_depth;
  if (!args.fine.empty() && s.has_rig()) app->LoadFineMaps(args.fine);
  const std::string library = !args.library.empty() ? args.library
                              : args.rig.empty()    ? ""
                                                    : DefaultLibraryPath(args.rig);
  if (!library.empty()) s.LoadLibraryFile(library);
  std::snprintf(app->library_field, sizeof app->library_field, "%s", library.c_str());
  if (!args.clip.empty() && s.has_rig() && s.LoadClipFile(args.clip)) {
    app->clip_time = args.time;
    app->pose_from_clip = true;
  }
  if (!args.clip.empty() && !s.has_rig() && !args.rig.empty())
    s.AddMessages({}, args.clip + ": not loaded (no rig to play it on)");
  std::snprintf(app->clip_field, sizeof app->clip_field, "%s", args.clip.c_str());
  if (!args.sets.empty() && s.has_rig()) s.ApplySettings(args.sets);
  if (!args.rig.empty() && !s.has_rig() && app->rig_field[0] == '\0')
    std::snprintf(app->rig_field, sizeof app->rig_field, "%s", args.rig.c_str());
  if (args.recover && s.RecoverAutosaves() > 0 && app->pose_from_clip && s.has_clip())
    s.SampleClip(app->clip_time);
  for (const std::string& panel : args.panels) {  // --panel: the rig editors to open
    app->show_muscle_editor |= panel == "muscle-editor";
    app->show_uv_curves |= panel == "uv-curves";
    app->show_directions |= panel == "directions";
  }
  return !HasErrors(s);
}

void Render(App* app, int width, int height) {
  auto start = std::chrono::steady_clock::now();
  glViewport(0, 0, width, height);
  app->renderer.Draw(app->MakeDrawParams(float(width) / float(std::max(height, 1))));
  glFinish();
  app->stats.draw_ms = MillisecondsSince(start);
}

// False when the context came from EGL (no window): ImGui then gets its frame time here.
bool g_glfw_backend = true;

void UiFrame(App* app, int width, int height) {
  ImGui_ImplOpenGL3_NewFrame();
  if (g_glfw_backend)
    ImGui_ImplGlfw_NewFrame();
  else
    ImGui::GetIO().DeltaTime = 1.f / 60.f;
  ImGui::GetIO().DisplaySize = ImVec2(float(width), float(height));
  ImGui::NewFrame();
  DrawPanels(app, float(width), float(height));
  ImGui::Render();
}

// One frame into `path` at the command line's size (with the panels under --ui).
bool TakeScreenshot(const ViewerArgs& args, App* app, const std::string& path, std::string* error) {
  // The headless path draws only finished rigs: a rebuild of the edited rig is waited for, and
  // the mesh uploaded again (a script's rig edits may have swapped the rig in already).
  if (app->session.rig_stale()) app->session.WaitRigRebuild();  // running, or done, not taken
  if (app->session.has_rig()) app->OnRigRebuilt();
  const int w = args.width, h = args.height;
  if (!app->renderer.BindOffscreen(w, h)) {
    *error = "the offscreen framebuffer (" + std::to_string(w) + "x" + std::to_string(h) +
             ") is incomplete";
    return false;
  }
  app->dirty = true;
  app->Update();
  Render(app, w, h);
  if (args.ui) {
    // ImGui lays windows out over the first frames; draw a few, keep the last.
    for (int i = 0; i < 3; ++i) {
      UiFrame(app, w, h);
      Render(app, w, h);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }
  }
  glFinish();
  const Image image = Renderer::ReadPixels(w, h);
  app->renderer.UnbindOffscreen();
  Diagnostics diag;
  if (!SavePng(path, image, &diag)) {
    *error = diag.Format();
    while (!error->empty() && error->back() == '\n') error->pop_back();
    return false;
  }
  std::printf("mimetic-viewer: wrote %s (%dx%d)\n", path.c_str(), w, h);
  return true;
}

int Headless(const ViewerArgs& args, App* app, GLFWwindow* window) {
  if (!LoadInputs(args, app)) {
    PrintMessages(app->session);
    std::fprintf(stderr, "mimetic-viewer: %s\n",
                 args.screenshot.empty() ? "nothing was measured" : "no screenshot was written");
    return kExitInput;
  }
  PrintMessages(app->session);  // warnings
  app->overlay = args.overlay;
  app->camera.SetPreset(args.view);
  if (!args.select.empty()) {
    app->selected_muscle = app->session.rig().FindMuscle(args.select);
    if (app->selected_muscle < 0) {
      std::fprintf(stderr, "error: --select %s: the rig %s has no such muscle\n",
                   args.select.c_str(), args.rig.c_str());
      return kExitInput;
    }
  }
  if (app->pose_from_clip) app->session.SampleClip(app->clip_time);
  if (!args.script.empty()) {
    ScriptHooks hooks;
    hooks.screenshot = [&](const std::string& path, std::string* error) {
      return TakeScreenshot(args, app, path, error);
    };
    hooks.playhead = [&](float t) {
      app->pose_from_clip = t >= 0.f;
      if (t >= 0.f) app->clip_time = t;
    };
    std::string error;
    const size_t before = app->session.messages().size();
    const bool ok = RunScriptFile(args.script, &app->session, hooks, &error);
    for (size_t i = before; i < app->session.messages().size(); ++i)
      if (!app->session.messages()[i].error)
        std::fprintf(stderr, "warning: %s\n", app->session.messages()[i].text.c_str());
    if (!ok) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return kExitInput;
    }
    if (args.screenshot.empty() && args.bench_frames == 0) return 0;
  }
  const int w = args.width, h = args.height;
  if (!app->renderer.BindOffscreen(w, h)) {
    std::fprintf(stderr, "mimetic-viewer: the offscreen framebuffer (%dx%d) is incomplete\n", w, h);
    return kExitInput;
  }
  if (args.bench_frames > 0) {
    // Each frame: the clip sampled at 1/60 s steps (when given), evaluate, upload, draw.
    double sum[4] = {0, 0, 0, 0}, worst[4] = {0, 0, 0, 0};
    for (int f = 0; f < args.bench_frames; ++f) {
      if (app->session.has_clip()) {
        const float d = app->session.clip().duration();
        app->clip_time = d > 0.f ? std::fmod(float(f) / 60.f, d) : 0.f;
        app->session.SampleClip(app->clip_time);
      } else {
        // Without a clip, alternate two poses so every frame does the same work.
        for (float& a : app->session.activations) a = (f % 2) ? 0.6f : 0.3f;
      }
      app->dirty = true;
      app->Update();
      Render(app, w, h);
      const double v[4] = {app->stats.evaluate_ms, app->stats.upload_ms,
                           app->stats.evaluate_ms + app->stats.upload_ms, app->stats.draw_ms};
      for (int i = 0; i < 4; ++i) {
        sum[i] += v[i];
        worst[i] = std::max(worst[i], v[i]);
      }
    }
    const double n = args.bench_frames;
    std::printf("mimetic-viewer bench: %s, %u vertices, %d frames, %u threads, %s\n",
                args.rig.c_str(), app->session.rig().vertex_count(), args.bench_frames,
                app->session.threads(), reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    const char* names[4] = {"evaluate", "upload", "evaluate+upload", "draw"};
    for (int i = 0; i < 4; ++i)
      std::printf("  %-16s mean %7.3f ms  worst %7.3f ms\n", names[i], sum[i] / n, worst[i]);
    if (args.screenshot.empty()) return 0;
  }
  (void)window;
  app->renderer.UnbindOffscreen();
  std::string error;
  if (!TakeScreenshot(args, app, args.screenshot, &error)) {
    std::fprintf(stderr, "mimetic-viewer: %s\n", error.c_str());
    return kExitInput;
  }
  return 0;
}

void Interactive(App* app, GLFWwindow* window) {
  double last = glfwGetTime();
  float last_x = -1.f, last_y = -1.f;
  while (true) {
    // Closing the window (its button or Ctrl+Q) with unsaved edits asks first (SafetyPopups
    // in panels.cpp).
    if (app->quit_requested) {
      app->quit_requested = false;
      glfwSetWindowShouldClose(window, GLFW_TRUE);
    }
    if (glfwWindowShouldClose(window) || app->close_confirmed) {
      if (app->close_confirmed || !app->unsaved()) break;
      glfwSetWindowShouldClose(window, GLFW_FALSE);
      app->close_requested = true;
    }
    glfwPollEvents();
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    const double now = glfwGetTime();
    const float dt = float(now - last);
    ImGuiIO& io = ImGui::GetIO();
    Session& s = app->session;
    if (app->autosave_seconds > 0.0 && now - app->last_autosave >= app->autosave_seconds) {
      s.Autosave();  // only what changed since the last save or autosave
      app->last_autosave = now;
    }
    // Playback at the fps the Clip panel sets: a new pose every 1/fps seconds.
    if (app->playing && s.has_clip() && dt >= 1.f / app->fps) {
      bool stopped = false;
      app->clip_time = AdvancePlayhead(app->clip_time, dt * app->speed, s.clip().duration(),
                                       app->loop, &stopped);
      if (stopped) app->playing = false;
      app->dirty = true;
      last = now;
    } else if (!app->playing) {
      last = now;
    }
    if (app->dirty && app->pose_from_clip) s.SampleClip(app->clip_time);
    // Camera: left drag orbits, right or middle drag (or shift + left) pans, the wheel zooms.
    if (!io.WantCaptureMouse) {
      const bool pan = io.MouseDown[1] || io.MouseDown[2] || (io.MouseDown[0] && io.KeyShift);
      if (pan) app->camera.Pan(io.MouseDelta.x, io.MouseDelta.y, float(h));
      else if (io.MouseDown[0]) app->camera.Orbit(io.MouseDelta.x, io.MouseDelta.y);
      if (io.MouseWheel != 0.f) app->camera.Zoom(io.MouseWheel);
      const bool moved = io.MousePos.x != last_x || io.MousePos.y != last_y;
      if (moved && !io.MouseDown[0] && !io.MouseDown[1] && !io.MouseDown[2]) {
        int ww = 0, wh = 0;
        glfwGetWindowSize(window, &ww, &wh);
        app->Hover(io.MousePos.x, io.MousePos.y, float(ww), float(wh));
      }
      last_x = io.MousePos.x;
      last_y = io.MousePos.y;
    } else {
      app->hover_valid = false;
    }
    if (!io.WantCaptureKeyboard) {
      const float3 lo = s.bounds_lo(), hi = s.bounds_hi();
      if (ImGui::IsKeyPressed(GLFW_KEY_F)) app->camera.Frame({lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z});
      if (ImGui::IsKeyPressed(GLFW_KEY_1)) app->camera.SetPreset(ViewPreset::kFront);
      if (ImGui::IsKeyPressed(GLFW_KEY_2)) app->camera.SetPreset(ViewPreset::kSide);
      if (ImGui::IsKeyPressed(GLFW_KEY_3)) app->camera.SetPreset(ViewPreset::kThreeQuarter);
      if (ImGui::IsKeyPressed(GLFW_KEY_W)) app->wireframe = !app->wireframe;
      if (ImGui::IsKeyPressed(GLFW_KEY_SPACE) && s.has_clip()) {
        app->playing = !app->playing;
        app->pose_from_clip = true;
      }
    }
    HandleEditShortcuts(app);
    // A finished rebuild of the edited rig is swapped in here, between frames.
    if (s.PollRigRebuild()) app->OnRigRebuilt();
    if (s.PollRigLoad()) app->OnRigLoaded();
    app->Update();
    int ww = 0, wh = 0;
    glfwGetWindowSize(window, &ww, &wh);
    UiFrame(app, ww, wh);
    int wx = 0, wy = 0;
    glfwGetWindowPos(window, &wx, &wy);
    WriteUiTrace(app, wx, wy);
    Render(app, w, h);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(window);
  }
}

int Main(int argc, char** argv) {
  ViewerArgs args;
  std::string error;
  if (!ParseViewerArgs(std::vector<std::string>(argv + 1, argv + argc), &args, &error)) {
    std::fprintf(stderr, "mimetic-viewer: %s\n\n%s", error.c_str(), ViewerUsage());
    return kExitUsage;
  }
  if (args.help) return std::fputs(ViewerUsage(), stdout), 0;
  if (const char* e = std::getenv("MIMETIC_TEST_EXIT_BEFORE_RENAME"); e && *e) {
    g_exit_before_rename = e;
    SetWriteFileAtomicHook(&ExitBeforeRename);
  }
  // Headless runs make their context through EGL when asked to or when there is no X display
  // (a GPU server, a container): no window is needed, the frames go to an offscreen target.
  const char* display = std::getenv("DISPLAY");
  const bool egl = args.headless() && (args.egl || !display || !*display);
  EglContext egl_context;
  GLFWwindow* window = nullptr;
  if (egl) {
    if (!egl_context.Create(&error)) {
      std::fprintf(stderr, "mimetic-viewer: %s\n", error.c_str());
      return kExitInput;
    }
    g_glfw_backend = false;
    if (args.bench_frames > 0)
      std::printf("mimetic-viewer: OpenGL through EGL, %s\n", egl_context.description().c_str());
  } else {
    if (!glfwInit()) {
      std::fprintf(stderr, "mimetic-viewer: cannot start GLFW (no display? the window needs one; "
                           "headless runs can use --egl or xvfb-run -a mimetic-viewer ...)\n");
      return kExitInput;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    if (args.headless()) glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    window = glfwCreateWindow(args.headless() ? args.width : 1600,
                              args.headless() ? args.height : 950, "mimetic-viewer", nullptr,
                              nullptr);
    if (!window) {
      std::fprintf(stderr, "mimetic-viewer: cannot create an OpenGL 3.3 core context\n");
      glfwTerminate();
      return kExitInput;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(args.headless() ? 0 : 1);
  }
  int rc = 0;
  {
    App app(unsigned(args.threads));
    if (!app.renderer.Init(&error)) {
      std::fprintf(stderr, "mimetic-viewer: %s\n", error.c_str());
      rc = kExitInput;
    } else {
      IMGUI_CHECKVERSION();
      ImGui::CreateContext();
      ImGui::GetIO().IniFilename = nullptr;  // layout is not saved between runs
      ImGui::StyleColorsDark();
      if (window) ImGui_ImplGlfw_InitForOpenGL(window, true);
      ImGui_ImplOpenGL3_Init("#version 330 core");
      if (args.headless()) {
        rc = Headless(args, &app, window);
      } else {
        LoadInputs(args, &app);
        app.autosave_seconds = args.autosave_seconds;
        app.ui_trace_path = args.ui_trace;
        app.last_autosave = glfwGetTime();
        app.offer_recovery = !args.recover && !app.session.PendingAutosaves().empty();
        Interactive(&app, window);
      }
      ReleaseRigPanels(&app);
      ImGui_ImplOpenGL3_Shutdown();
      if (window) ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
      app.renderer.Shutdown();
    }
  }
  if (window) {
    glfwDestroyWindow(window);
    glfwTerminate();
  }
  return rc;
}

}  // namespace
}  // namespace mimetic::viewer

int main(int argc, char** argv) {
  try {
    return mimetic::viewer::Main(argc, argv);
  } catch (const std::exception& e) {  // the runtime throws none; the standard library may
    std::fprintf(stderr, "mimetic-viewer: internal error: %s\n", e.what());
    return 1;
  }
}
