// tools/commands.h: the `mimetic` subcommands. Each takes its arguments (after the command
// name) and returns the process exit code: 0 success, 1 bad input or failure, 2 bad usage.
#pragma once

#include <string>
#include <vector>

namespace mimetic::tools {

using Args = std::vector<std::string>;

int CmdInfo(const Args& args);
int CmdValidate(const Args& args);
int CmdEval(const Args& args);
int CmdBuild(const Args& args);       // the compiled rig .mrig (tools/cmd_build.cpp)
int CmdMakeSurface(const Args& args);  // the procedural test surface
int CmdMakeHead(const Args& args);     // the sample head (tools/cmd_head.cpp)
int CmdTexture(const Args& args);      // fine-scale wrinkle maps (tools/cmd_texture.cpp)
int CmdRender(const Args& args);       // software render to PNG (tools/cmd_render.cpp)
int CmdFit(const Args& args);          // place a muscle template on a head (tools/cmd_fit.cpp)
int CmdCompare(const Args& args);      // how close a mesh is to another (tools/cmd_compare.cpp)
int CmdSolve(const Args& args);        // activations closest to a target shape (tools/cmd_solve.cpp)
int CmdFidelity(const Args& args);     // the fidelity report on ICT-FaceKit (tools/cmd_fidelity.cpp)
int CmdCreases(const Args& args);      // crease numbers of the muscles (tools/cmd_creases.cpp)
int CmdCalibrate(const Args& args);    // calibrate a template on real shapes (tools/cmd_calibrate.cpp)
int CmdCalibrateJaw(const Args& args); // calibrate the template's jaw on ICT's jawOpen (tools/cmd_calibrate_jaw.cpp)
int CmdPlay(const Args& args);         // sample a clip and pose the rig (tools/cmd_play.cpp)
int CmdImportArkit(const Args& args);  // a face-capture take into a clip (tools/cmd_import_arkit.cpp)
int CmdMakeLibrary(const Args& args);
int CmdExportBlendshapes(const Args& args);  // 52 ARKit morph targets (tools/cmd_export_blendshapes.cpp)  // the expression library and ARKit map (tools/cmd_library.cpp)

}  // namespace mimetic::tools
