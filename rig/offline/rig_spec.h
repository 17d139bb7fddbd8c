// rig/offline/rig_spec.h: the rig file (docs/rig-format.md) once parsed, before compiling.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "muscles/offline/muscle_spec.h"

namespace mimetic {

// Subcutaneous skin thickness h (MODEL.md §4), in mesh units.
struct ThicknessSpec {
  enum class Kind { kConstant, kPerVertex, kImage };
  Kind kind = Kind::kConstant;
  float value = 0.f;               // kConstant
  std::vector<float> per_vertex;   // kPerVertex: one per file vertex
  std::string image_path;          // kImage: absolute or relative to the cwd (resolved)
  float min = 0.f, max = 0.f;      // kImage: black -> min, white -> max
};

struct RigSpec {
  std::string file;        // the rig file this came from ("" when parsed from text)
  std::string mesh_path;   // resolved against the rig file's directory
  std::string mesh_name;   // glTF mesh name; "" = first mesh
  std::string units;       // "mm", "cm", "dm", "m" or "in"
  ThicknessSpec thickness;
  std::vector<MuscleSpec> muscles;
};

// Parses and validates a rig file. Every problem is recorded with its JSON path
// (`muscles[3].insertion: expected array of 3 numbers, got string`); returns false when any
// error was recorded. `base_dir` resolves relative paths ("" = current directory).
bool ParseRigSpec(std::string_view json_text, const std::string& base_dir, RigSpec* out,
                  Diagnostics* diag);
bool LoadRigSpec(const std::string& path, RigSpec* out, Diagnostics* diag);

// Writes the rig file atomically (temp file + rename). Paths are written relative to the
// directory of `path` where possible.
bool SaveRigSpec(const std::string& path, const RigSpec& spec, Diagnostics* diag);

}  // namespace mimetic
