// tools/play_inputs.h: what every form of `mimetic play` reads first (the rig, the clip, the
// --expression and --library files) and the clip built on the rig.
#pragma once

#include "expressions/runtime/clip.h"
#include "io/rig_loader.h"
#include "tools/cli.h"

namespace mimetic::tools {

// Loads RIG (positional 0) and CLIP (positional 1), the --expression and --library files, and
// builds the clip on the rig's muscles. Every problem of every file is collected; on failure
// they are printed with one closing line ending in `nothing_written` ("nothing was written")
// and false is returned. On success `diag` keeps the warnings for the caller to print.
// CLIP may be a compiled clip (.mclip, IsCompiledClipPath): it is read as it is (the
// --expression and --library files are not needed then, and a warning says they are unused)
// and refused unless it was compiled for a rig of RIG's muscle count.
bool LoadPlayInputs(const ParsedArgs& parsed, const char* nothing_written, LoadedRig* loaded,
                    CompiledClip* clip, Diagnostics* diag);

// The same with the paths given and `command` naming the command in the closing line
// ("mimetic COMMAND: ..."); `mimetic build CLIP --rig RIG` uses it.
bool LoadClipInputs(const std::string& command, const std::string& rig_path,
                    const std::string& clip_path, const ParsedArgs& parsed,
                    const char* nothing_written, LoadedRig* loaded, CompiledClip* clip,
                    Diagnostics* diag);

}  // namespace mimetic::tools
