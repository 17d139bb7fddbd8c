// io/formats.h: the declared formats (for their schemas) and the blocks two formats share.
// Declared on the reader of io/json_reader.h.
#pragma once

#include <string>

#include "io/json_reader.h"

namespace mimetic {
// The formats' declarations, for their schemas (defined in io/rig_file.cpp,
// io/template_file.cpp, io/landmarks_file.cpp).
const json_reader::Format& RigFileFormat();
const json_reader::Format& TemplateFileFormat();
const json_reader::Format& LandmarksFileFormat();
const json_reader::Format& ExpressionFileFormat();  // io/expression_file.cpp
const json_reader::Format& ClipFileFormat();        // io/clip_file.cpp
const json_reader::Format& ExpressionLibraryFormat();  // io/expression_library.cpp
const json_reader::Format& ArkitMapFormat();  // io/arkit_map.cpp
const json_reader::Format& ArkitTakeFormat();  // io/arkit_take.cpp (JSON takes)

// A block that two formats share (defined in io/rig_file.cpp): the muscle wrinkle block of
// docs/model.md §6, in rig files (mesh units) and templates (units of s, docs/template-format.md).
// The table for a linear (`linear`) or a sheet muscle, lengths in `unit`; and the reading of a
// checked block `w` of the muscle `m`: the attenuation key (phi_c_deg, h_c) is bounded by m's
// zone_angle_deg or width/2 where those were read. False when a rule is broken (reported).
struct MuscleWrinkleSpec;
json_reader::Object MuscleWrinkleBlock(bool linear, const std::string& unit);
bool ReadMuscleWrinkles(const json_reader::View& w, const json_reader::View& m, bool linear,
                        MuscleWrinkleSpec* out);
}  // namespace mimetic
