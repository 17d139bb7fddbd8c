// io/arkit_take.h: face-capture takes (ARKit blendshape weights per frame) read from the CSV
// that capture apps export and from a JSON array of frames (docs/arkit.md, "Importing a
// take"). The conversion into a clip is expressions/offline/arkit_import.h.
//
// CSV (Live Link Face style): a header row, then one row per frame.
//   Timecode,BlendShapeCount,EyeBlinkLeft,...,JawOpen,...
//   00:00:01:00.000,61,0.12,...,0.30,...
// - time: a `Timecode` column HH:MM:SS:FF or HH:MM:SS:FF.fff (FF the frame at `fps`, .fff
//   a fraction of a frame), or a `Time` / `Seconds` column in seconds (headers compared case-
//   insensitively); times are taken relative to the first row and must increase strictly.
// - `BlendShapeCount` is ignored; every other column is a channel named by its header.
// - every cell a number; the cells of ARKit names (Apple's, either case of the first letter)
//   in [0, 1]. Other channels (HeadYaw, ...) may hold any finite number (the import lists them).
// JSON: [{"time": 0.0, "blendshapes": {"jawOpen": 0.3, ...}}, ...]: times in seconds, >= 0,
// strictly increasing (taken relative to the first); a channel a frame omits is 0 there.
#pragma once

#include <string>

#include "core/diagnostics.h"
#include "expressions/offline/arkit_import.h"

namespace mimetic {

// Every problem is an error naming where: CSV "FILE:LINE:COLUMN (HEADER)" (1-based), JSON the
// path ("[3].blendshapes.jawOpen"). False on any error. `fps` (> 0) reads timecodes.
bool ParseArkitCsv(const std::string& text, const std::string& where, double fps,
                   ArkitTake* out, Diagnostics* diag);
bool ParseArkitTakeJson(const std::string& text, const std::string& where, ArkitTake* out,
                        Diagnostics* diag);
// By extension: .csv, or .json.
bool LoadArkitTake(const std::string& path, double fps, ArkitTake* out, Diagnostics* diag);

// True when `name` is one of Apple's 52 (or the same with the other case of its first letter).
bool IsArkitName(const std::string& name);

}  // namespace mimetic
