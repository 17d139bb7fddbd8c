// viewer/core/args.cpp: see args.h.
#include "viewer/core/args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace mimetic::viewer {
namespace {

// The whole of `text` as a base-10 integer in [lo, hi].
bool WholeInt(const std::string& text, long lo, long hi, int* out) {
  if (text.empty() || (text[0] != '-' && !std::isdigit(static_cast<unsigned char>(text[0]))))
    return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (*end != '\0' || errno == ERANGE || v < lo || v > hi) return false;
  *out = int(v);
  return true;
}

bool EndsWithPng(const std::string& path) {
  if (path.size() < 5) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png";
}

}  // namespace

const char* ViewerUsage() {
  return "usage: mimetic-viewer [RIG] [--clip CLIP] [--library LIB]\n"
         "                      [--time T | --set NAME=VALUE ...]\n"
         "                      [--screenshot OUT.png [--size WxH] [--overlay NAME]\n"
         "                       [--view front|side|three-quarter] [--ui] [--select MUSCLE]]\n"
         "                      [--panel muscle-editor|uv-curves|directions]\n"
         "                      [--bench-frames N] [--threads N]\n"
         "                      [--script FILE] [--autosave-seconds N] [--recover]\n"
         "                      [--fine DIR [--fine-depth D]] [--ui-trace FILE] [--egl]\n\n"
         "Shows RIG (a .rig.json or a compiled .mrig) live: orbit, pan and zoom, skin shading,\n"
         "overlays, a slider per muscle, expressions and clips (docs/viewer.md). A file that\n"
         "fails to load is reported in the Messages panel; the viewer keeps what it had.\n\n"
         "options:\n"
         "  --clip CLIP          a clip (.clip.json or .mclip) to play\n"
         "  --library LIB        the expression library (default: assets/expressions/\n"
         "                       default.library.json found from the rig's folder upwards)\n"
         "  --time T             the clip time in seconds for a screenshot (needs --clip)\n"
         "  --set NAME=VALUE     a muscle activation in [0, 1] (repeatable; NAME sets NAME_L and\n"
         "                       NAME_R; jaw=VALUE opens the jaw)\n"
         "  --screenshot OUT.png render one frame into OUT.png (written atomically) and exit:\n"
         "                       exit 0 done, 1 an input failed (messages on stderr), 2 usage\n"
         "  --size WxH           the screenshot's size in pixels (default 1280x720)\n"
         "  --overlay NAME       colour the skin by a field: none, area-ratio, shrinkage,\n"
         "                       compression, wrinkle, thickness, displacement\n"
         "  --view V             the camera preset: front (default), side, three-quarter\n"
         "  --ui                 draw the panels into the screenshot\n"
         "  --select MUSCLE      draw MUSCLE's gizmos (attachment, insertion, zone or sheet\n"
         "                       outline, wrinkling region) in the screenshot\n"
         "  --panel NAME         open a rig editor at the start (repeatable): muscle-editor\n"
         "                       (the --select muscle's parameters), uv-curves, directions\n"
         "  --bench-frames N     evaluate, upload and draw N frames headless (playing the clip\n"
         "                       if one is given) and print the mean and worst times\n"
         "  --threads N          evaluation threads (default: the hardware's; 1 = serial)\n"
         "  --script FILE        run FILE's edit commands headless (docs/viewer.md \"Scripts\")\n"
         "                       and exit: 0 done, 1 with FILE:LINE: message on a bad line\n"
         "  --autosave-seconds N write the unsaved clip, library and rig to FILE.autosave\n"
         "                       every N seconds (default 60; 0 = never)\n"
         "  --recover            take the clip's, library's and rig's .autosave files (newer\n"
         "                       edits that were never saved) at the start, without asking\n"
         "  --fine DIR           bump-map the skin with DIR/fine_height_1.png and\n"
         "                       fine_height_2.png (`mimetic texture RIG --out DIR`), each\n"
         "                       scaled per vertex by the evaluator's fine-scale amplitude\n"
         "  --fine-depth D       a full furrow's depth at amplitude 1, mesh units (default\n"
         "                       0.15; needs --fine)\n"
         "  --ui-trace FILE      (the window only; for tests) after each frame, write the\n"
         "                       screen rectangles of the widgets the UI tests drive to FILE\n"
         "                       as JSON (written atomically; docs/viewer.md \"Tested by\n"
         "                       driving the UI\")\n"
         "  --egl                (headless runs) make the OpenGL context through EGL, with no\n"
         "                       window and no X display: a GPU's driver directly, or Mesa's\n"
         "                       surfaceless platform; the default when DISPLAY is not set\n"
         "  -h, --help           this text\n";
}

bool ParseViewerArgs(const std::vector<std::string>& args, ViewerArgs* out, std::string* error) {
  *out = ViewerArgs{};
  bool has_size = false, has_overlay = false, has_view = false;
  std::vector<std::string> positional;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string a = args[i], value;
    bool has_inline = false;
    if (a.rfind("--", 0) == 0) {
      const size_t eq = a.find('=');
      if (eq != std::string::npos) {
        value = a.substr(eq + 1);
        a = a.substr(0, eq);
        has_inline = true;
      }
    }
    if (a == "-h" || a == "--help") {
      out->help = true;
      return true;
    }
    if (a == "--ui") {
      out->ui = true;
      continue;
    }
    if (a == "--recover") {
      out->recover = true;
      continue;
    }
    if (a == "--egl") {
      out->egl = true;
      continue;
    }
    static const char* kValued[] = {"--clip", "--library", "--time", "--set", "--screenshot",
                                    "--size", "--overlay", "--view", "--select", "--panel", "--bench-frames",
                                    "--threads", "--script", "--autosave-seconds", "--fine",
                                    "--fine-depth", "--ui-trace"};
    bool valued = false;
    for (const char* k : kValued) valued = valued || a == k;
    if (!valued) {
      if (a.size() > 1 && a[0] == '-') {
        *error = "unknown option " + args[i];
        return false;
      }
      positional.push_back(a);
      continue;
    }
    if (!has_inline) {
      if (i + 1 >= args.size()) {
        *error = a + ": missing value";
        return false;
      }
      value = args[++i];
    }
    if (a == "--clip") {
      out->clip = value;
    } else if (a == "--library") {
      out->library = value;
    } else if (a == "--ui-trace") {
      if (value.empty()) {
        *error = "--ui-trace: expected a file to write";
        return false;
      }
      out->ui_trace = value;
    } else if (a == "--select") {
      out->select = value;
    } else if (a == "--panel") {
      if (value != "muscle-editor" && value != "uv-curves" && value != "directions") {
        *error = "--panel " + value + ": expected muscle-editor, uv-curves or directions";
        return false;
      }
      out->panels.push_back(value);
    } else if (a == "--script") {
      out->script = value;
    } else if (a == "--autosave-seconds") {
      if (!WholeInt(value, 0, 86400, &out->autosave_seconds)) {
        *error = "--autosave-seconds " + value + ": expected a whole number of seconds in [0, 86400]";
        return false;
      }
    } else if (a == "--set") {
      out->sets.push_back(value);
    } else if (a == "--screenshot") {
      if (!EndsWithPng(value)) {
        *error = "--screenshot " + value + ": expected a .png file name";
        return false;
      }
      out->screenshot = value;
    } else if (a == "--fine") {
      out->fine = value;
    } else if (a == "--fine-depth") {
      char* end = nullptr;
      errno = 0;
      const double d = value.empty() ? NAN : std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(d) || d < 0.0 || d > 1e6) {
        *error = "--fine-depth " + value + ": expected a depth in mesh units in [0, 1e6]";
        return false;
      }
      out->has_fine_depth = true;
      out->fine_depth = float(d);
    } else if (a == "--time") {
      char* end = nullptr;
      errno = 0;
      const double t = value.empty() ? NAN : std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(t) || t < 0.0) {
        *error = "--time " + value + ": expected a number of seconds >= 0";
        return false;
      }
      out->has_time = true;
      out->time = float(t);
    } else if (a == "--size") {
      const size_t x = value.find('x');
      if (x == std::string::npos || !WholeInt(value.substr(0, x), 16, 8192, &out->width) ||
          !WholeInt(value.substr(x + 1), 16, 8192, &out->height)) {
        *error = "--size " + value + ": expected WIDTHxHEIGHT, each in [16, 8192] (e.g. 1280x720)";
        return false;
      }
      has_size = true;
    } else if (a == "--overlay") {
      if (!ParseOverlay(value, &out->overlay)) {
        *error = "--overlay " + value + ": expected one of " + OverlayNames();
        return false;
      }
      has_overlay = true;
    } else if (a == "--view") {
      if (!ParseViewPreset(value, &out->view)) {
        *error = "--view " + value + ": expected front, side or three-quarter";
        return false;
      }
      has_view = true;
    } else if (a == "--bench-frames") {
      if (!WholeInt(value, 1, 1000000, &out->bench_frames)) {
        *error = "--bench-frames " + value + ": expected a whole number of frames >= 1";
        return false;
      }
    } else if (a == "--threads") {
      if (!WholeInt(value, 1, 256, &out->threads)) {
        *error = "--threads " + value + ": expected a whole number in [1, 256]";
        return false;
      }
    }
  }
  if (positional.size() > 1) {
    *error = "expected at most one RIG, got " + std::to_string(positional.size()) +
             " (" + positional[0] + ", " + positional[1] + (positional.size() > 2 ? ", ..." : "") + ")";
    return false;
  }
  if (!positional.empty()) out->rig = positional[0];
  if (out->has_fine_depth && out->fine.empty()) {
    *error = "--fine-depth needs --fine DIR (the maps it scales)";
    return false;
  }
  if (out->has_time && out->clip.empty()) {
    *error = "--time needs --clip CLIP (the time is a time in the clip)";
    return false;
  }
  if (!out->sets.empty() && !out->clip.empty()) {
    *error = "--set and --clip exclude each other (the clip sets the activations)";
    return false;
  }
  if ((has_size || has_overlay || has_view || out->ui || !out->select.empty()) &&
      out->screenshot.empty() && out->bench_frames == 0 && out->script.empty()) {
    *error = "--size, --overlay, --view, --ui and --select need --screenshot OUT.png (or "
             "--bench-frames, or --script)";
    return false;
  }
  if (!out->ui_trace.empty() && out->headless()) {
    *error = "--ui-trace traces the window's widgets: it excludes --screenshot, --bench-frames "
             "and --script";
    return false;
  }
  if (out->egl && !out->headless()) {
    *error = "--egl makes a headless run's context: it needs --screenshot, --bench-frames or "
             "--script (the window uses the display)";
    return false;
  }
  if (out->headless() && out->rig.empty()) {
    *error = "--screenshot, --bench-frames and --script need RIG";
    return false;
  }
  return true;
}

}  // namespace mimetic::viewer
