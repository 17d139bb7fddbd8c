// io/rig_file.h: the rig file (docs/rig-format.md, assets/schema/mimetic-rig.schema.json).
#pragma once

#include <string>
#include <string_view>

#include "core/diagnostics.h"
#include "rig/offline/rig_spec.h"

namespace mimetic {

// Parses and validates a rig file. Every problem is recorded with its JSON path
// (`muscles[3].insertion: expected array of 3 numbers, got string`); returns false when any
// error was recorded. `base_dir` resolves relative paths ("" = current directory).
bool ParseRigSpec(std::string_view json_text, const std::string& base_dir, RigSpec* out,
                  Diagnostics* diag);
bool LoadRigSpec(const std::string& path, RigSpec* out, Diagnostics* diag);

// Writes the rig file atomically (temp file + rename). Paths are written relative to the
// directory of `path` where possible.
bool SaveRigSpec(const std::string& path, const RigSpec& spec, Diagnostics* diag);

// The text SaveRigSpec writes for a file in directory `dir` (nothing is checked or written):
// the same spec gives the same bytes, and every float is written so that it reads back to the
// same bits (the viewer compares specs by it). "" with *error when it cannot be written (a name
// that is not UTF-8).
std::string RigSpecText(const RigSpec& spec, const std::string& dir, std::string* error = nullptr);

}  // namespace mimetic
