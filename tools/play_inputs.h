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
bool LoadPlayInputs(const ParsedArgs& parsed, const char* nothing_written, LoadedRig* loaded,
                    CompiledClip* clip, Diagnostics* diag);

}  // namespace mimetic::tools
