// io/landmarks_file.h: landmark files (docs/landmarks-format.md).
#pragma once

#include <string>

#include "core/diagnostics.h"
#include "fitting/landmarks.h"

namespace mimetic {

// Parses the JSON text of a landmark file. Records every problem with its JSON path and what
// was expected (wrong count, non-finite numbers, wrong types, unknown keys, unknown scheme or
// format, unsupported version); returns false when any error was recorded. `where` prefixes
// the messages (usually the file name).
bool ParseLandmarks(const std::string& json_text, const std::string& where, Landmarks* out,
                    Diagnostics* diag);

// Reads a landmark file (ParseLandmarks on its contents).
bool LoadLandmarks(const std::string& path, Landmarks* out, Diagnostics* diag);

// The JSON text of `landmarks` (points always when present; "vertices" when given).
std::string LandmarksToJson(const Landmarks& landmarks);

// Writes the file atomically. Refuses (false, with a message) landmarks that would not load
// back: wrong counts, non-finite points, neither points nor vertices.
bool SaveLandmarks(const std::string& path, const Landmarks& landmarks, Diagnostics* diag);

}  // namespace mimetic
