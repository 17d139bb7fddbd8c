// tools/play_golden.h: `mimetic play RIG CLIP --write-golden DIR [--frames t1,t2,...]`, the only
// way to (re)write a playback golden (tests/golden/README.md).
#pragma once

#include "tools/cli.h"

namespace mimetic::tools {

// The usage lines `mimetic play --help` adds for --write-golden.
extern const char* kPlayGoldenUsage;

// Runs the --write-golden form of `mimetic play` (parsed.Has("write-golden")): writes
// DIR/<clip name>.golden (atomically) for the clip at the --frames times (default: a quarter,
// half and all of the clip's duration). Returns the exit code.
int PlayWriteGolden(const ParsedArgs& parsed);

}  // namespace mimetic::tools
