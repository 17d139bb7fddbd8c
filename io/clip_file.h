// io/clip_file.h: a clip, keyframed muscle activations and expression weights (JSON,
// "format": "mimetic-clip", version 1; docs/expressions.md, the schema
// assets/schema/mimetic-clip.schema.json generated from the table in io/clip_file.cpp).
//
//   {"format": "mimetic-clip", "version": 1, "name": "smile_and_blink",
//    "duration": 2.0, "end": "loop",
//    "channels": [
//      {"expression": "mouthSmile_L", "layer": "add",
//       "keys": [{"t": 0, "v": 0}, {"t": 1, "v": 1, "interp": "cubic"}, {"t": 2, "v": 0}]},
//      {"muscle": "frontalis_inner_L", "keys": [{"t": 0.5, "v": 0.8, "interp": "step"}]}]}
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "expressions/offline/clip_builder.h"
#include "expressions/offline/clip_spec.h"
#include "io/expression_file.h"

namespace mimetic {

// Parses a clip file. Records every problem with its JSON path: the generic ones of the reader
// (types, ranges, unknown, missing and duplicate keys, the version), a channel with both or
// neither of "muscle" and "expression", a "layer" on a muscle channel, then CheckClipSpec's
// rules (strictly increasing key times, each target once, the duration against the last key,
// a loop of 0 s). Returns false when any error was recorded; `where` prefixes the messages
// (usually the file name).
bool ParseClip(const std::string& text, const std::string& where, ClipSpec* out,
               Diagnostics* diag);
bool LoadClip(const std::string& path, ClipSpec* out, Diagnostics* diag);

// The JSON text of `clip`: every key written (interp and tangent included), numbers as the
// shortest text that reads back as the same float, so ParseClip(ClipToJson(c)) == c (a muscle
// channel's `layer`, which has no meaning, is not written and reads back as the default).
std::string ClipToJson(const ClipSpec& clip);

// Writes the file atomically (temp file + rename). Refuses (false, with the messages of
// CheckClipSpec prefixed with `path`) a clip that breaks a rule.
bool SaveClip(const std::string& path, const ClipSpec& clip, Diagnostics* diag);

// True when `path` names a compiled clip (expressions/runtime/clip_binary.h): it ends in
// .mclip (any case) or starts with the "MCLP" tag.
bool IsCompiledClipPath(const std::string& path);

// BuildClip on the expressions of expression files (io/expression_file.h).
bool BuildClip(const ClipSpec& clip, const std::vector<std::string>& muscle_names,
               const std::vector<Expression>& expressions, CompiledClip* out, Diagnostics* diag);

}  // namespace mimetic
