// viewer/core/args.h: mimetic-viewer's command line (docs/viewer.md "Command line").
//
//   mimetic-viewer [RIG] [--clip CLIP] [--library LIB] [--time T | --set NAME=V ...]
//                  [--screenshot OUT.png [--size WxH] [--overlay NAME] [--view V] [--ui] [--select MUSCLE]] [--panel NAME]
//                  [--bench-frames N] [--threads N] [--script FILE] [--autosave-seconds N] [--recover]
//                  [--fine DIR [--fine-depth D]] [--ui-trace FILE] [--egl]
#pragma once

#include <string>
#include <vector>

#include "viewer/core/camera.h"
#include "viewer/core/overlays.h"

namespace mimetic::viewer {

struct ViewerArgs {
  std::string rig;                // positional; may be empty (the viewer opens without a rig)
  std::string clip;               // --clip
  std::string library;            // --library (empty: the default library beside the rig)
  bool has_time = false;          // --time given
  float time = 0.f;               // --time seconds (needs --clip)
  std::vector<std::string> sets;  // --set NAME=VALUE, in order (checked against the rig later)
  std::string screenshot;         // --screenshot OUT.png: render one frame and exit
  int width = 1280, height = 720; // --size WxH, each in [16, 8192]
  Overlay overlay = Overlay::kNone;  // --overlay
  ViewPreset view = ViewPreset::kFront;  // --view
  bool ui = false;                // --ui: draw the panels into the screenshot
  std::string select;             // --select MUSCLE: the muscle whose gizmos are drawn
  // --panel NAME (repeatable): open a rig editor at the start: muscle-editor, uv-curves,
  // directions (docs/viewer.md "Editing the rig").
  std::vector<std::string> panels;
  int bench_frames = 0;           // --bench-frames N (>= 1): time N frames headless and exit
  int threads = 0;                // --threads N: evaluation threads (0: hardware threads)
  std::string script;             // --script FILE: run its edit commands headless and exit
  int autosave_seconds = 60;      // --autosave-seconds N (0: no autosave)
  bool recover = false;           // --recover: take the .autosave files at the start
  std::string fine;               // --fine DIR: the fine-scale height maps to bump-map with
  bool has_fine_depth = false;    // --fine-depth given (needs --fine)
  float fine_depth = 0.15f;       // --fine-depth D, mesh units
  std::string ui_trace;           // --ui-trace FILE: the window writes its widgets' rects (tests)
  bool egl = false;               // --egl: a headless run's context through EGL, no X display
  bool help = false;              // --help / -h
  bool headless() const { return !screenshot.empty() || bench_frames > 0 || !script.empty(); }
};

// Parses `args` (without the program name). On a usage problem returns false with `error` set
// to one line naming the option and what was expected; the caller prints it with the usage
// and exits 2. Rules: --time needs --clip; --set and --clip exclude each other; --size, --overlay,
// --view, --ui and --select need --screenshot (or --bench-frames or --script); a headless run needs RIG; --screenshot ends in .png;
// --egl needs a headless run.
bool ParseViewerArgs(const std::vector<std::string>& args, ViewerArgs* out, std::string* error);

// The usage text (--help).
const char* ViewerUsage();

}  // namespace mimetic::viewer
