// io/template_file.h: the muscle template file (docs/template-format.md).
#pragma once

#include <string>
#include <string_view>

#include "core/diagnostics.h"
#include "fitting/muscle_template.h"

namespace mimetic {

// Parses and validates a template (docs/template-format.md). Every problem is recorded with
// its JSON path and what was expected; returns false when any error was recorded.
bool ParseMuscleTemplate(std::string_view json_text, MuscleTemplate* out, Diagnostics* diag);
bool LoadMuscleTemplate(const std::string& path, MuscleTemplate* out, Diagnostics* diag);

// Writes a template in the file format: a mirrored pair as its source with `"mirror": true`,
// numbers to 4 significant digits, small objects on one line. Parsing the text gives back
// the template to those digits (`mimetic calibrate` writes its result with it).
std::string MuscleTemplateToJson(const MuscleTemplate& t);
bool SaveMuscleTemplate(const std::string& path, const MuscleTemplate& t, Diagnostics* diag);

}  // namespace mimetic
