// tools/main.cpp: the `mimetic` command line.
#include <cstdio>
#include <cstring>
#include <string>

#include "tools/commands.h"

namespace {

struct Command {
  const char* name;
  int (*run)(const mimetic::tools::Args&);
  const char* summary;
};

const Command kCommands[] = {
    {"info", mimetic::tools::CmdInfo, "print what a rig contains"},
    {"validate", mimetic::tools::CmdValidate, "check a rig and its mesh; list every problem"},
    {"eval", mimetic::tools::CmdEval, "pose a rig with muscle activations and write the mesh"},
    {"build", mimetic::tools::CmdBuild, "compile a rig into a .mrig the runtime loads alone"},
    {"make-surface", mimetic::tools::CmdMakeSurface, "write the procedural test surface mesh"},
    {"make-head", mimetic::tools::CmdMakeHead, "write the procedural sample head and its landmarks"},
    {"texture", mimetic::tools::CmdTexture, "carve the fine-scale wrinkle height and normal maps"},
    {"render", mimetic::tools::CmdRender, "render a mesh to a PNG image (software, no GPU)"},
    {"fit", mimetic::tools::CmdFit, "place a muscle template on a head from its landmarks"},
    {"compare", mimetic::tools::CmdCompare, "how close a mesh is to another (surface distance, motion)"},
    {"solve", mimetic::tools::CmdSolve, "the muscle activations closest to a target shape"},
    {"fidelity", mimetic::tools::CmdFidelity, "the fidelity report: the rig against ICT-FaceKit's real shapes"},
    {"creases", mimetic::tools::CmdCreases, "how sharply each muscle folds the skin at its zone's edges"},
    {"calibrate", mimetic::tools::CmdCalibrate, "calibrate a muscle template on real expression shapes"},
    {"calibrate-jaw", mimetic::tools::CmdCalibrateJaw, "calibrate the template's jaw on ICT-FaceKit's jawOpen"},
    {"play", mimetic::tools::CmdPlay, "sample a clip and write the posed mesh or an OBJ sequence"},
    {"import-arkit", mimetic::tools::CmdImportArkit, "turn a face-capture take (ARKit CSV/JSON) into a clip"},
    {"export-blendshapes", mimetic::tools::CmdExportBlendshapes, "the rig at the 52 ARKit shapes as a glTF with named morph targets"},
    {"make-library", mimetic::tools::CmdMakeLibrary, "the expression library and ARKit map, solved on ICT-FaceKit"},
};

void PrintHelp(FILE* out) {
  std::fprintf(out,
               "mimetic: a muscle-driven facial rig with wrinkles\n\n"
               "usage: mimetic <command> [arguments]    (mimetic <command> --help for details)\n\n"
               "commands:\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-13s %s\n", c.name, c.summary);
  std::fprintf(out, "\nexit status: 0 success, 1 bad input or failure, 2 bad usage\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    PrintHelp(stderr);
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    PrintHelp(stdout);
    return 0;
  }
  if (name == "--version") {
    std::printf("mimetic 0.1.0\n");
    return 0;
  }
  for (const Command& c : kCommands) {
    if (name == c.name) return c.run(mimetic::tools::Args(argv + 2, argv + argc));
  }
  std::fprintf(stderr, "mimetic: unknown command '%s'\n\n", name.c_str());
  PrintHelp(stderr);
  return 2;
}
