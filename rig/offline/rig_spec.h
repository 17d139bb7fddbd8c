// rig/offline/rig_spec.h: the rig file (docs/rig-format.md) once parsed, before compiling.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "core/image.h"
#include "geometry/fingerprint.h"
#include "muscles/offline/muscle_spec.h"
#include "rig/runtime/skin_layers.h"
#include "wrinkles/offline/wrinkle_spec.h"

namespace mimetic {

// Subcutaneous skin thickness h (docs/model.md §4), in mesh units.
struct ThicknessSpec {
  enum class Kind { kConstant, kPerVertex, kImage };
  Kind kind = Kind::kConstant;
  float value = 0.f;               // kConstant
  std::vector<float> per_vertex;   // kPerVertex: one per file vertex
  std::string image_path;          // kImage: absolute or relative to the cwd (resolved)
  GrayImage image;                 // kImage: its pixels, decoded by io (LoadRig) before BuildRig
  float min = 0.f, max = 0.f;      // kImage: black -> min, white -> max
};

// Compile-time refinement (docs/model.md §11): triangles in a wrinkle's support are split until
// their edges are shorter than `edge_fraction` times the wrinkle's width.
struct RefinementSpec {
  bool enabled = true;
  float edge_fraction = 0.25f;  // (0, 1]
};

struct NamedCurveWrinkle {
  std::string name;             // unique among curve wrinkles
  CurveWrinkleSpec spec;
};

struct RigSpec {
  std::string file;        // the rig file this came from ("" when parsed from text)
  std::string mesh_path;   // resolved against the rig file's directory
  std::string mesh_name;   // glTF mesh name; "" = first mesh
  // The mesh the per-vertex and texture-space data were made for (`mesh.fingerprint`,
  // geometry/fingerprint.h); empty in files written before it existed. BuildRig refuses a mesh
  // that does not match it when the rig has per-vertex thickness (positions and indices) or a
  // thickness image or curve wrinkles (texture coordinates too).
  MeshFingerprint mesh_fingerprint;
  std::string units;       // "mm", "cm", "dm", "m" or "in"
  ThicknessSpec thickness;
  std::vector<MuscleSpec> muscles;
  // Parallel to `muscles`: the optional wrinkle block of each muscle (docs/model.md §6). Empty
  // vector or nullopt entries mean no wrinkles. (Kept here, not in MuscleSpec, because
  // muscles/ and wrinkles/ are siblings that do not include each other.)
  std::vector<std::optional<MuscleWrinkleSpec>> muscle_wrinkles;
  std::vector<NamedCurveWrinkle> curve_wrinkles;  // docs/model.md §7-8
  SkinLayers layers;  // which skin layers to compile (all by default); docs/model.md §1 steps 3-4
  RefinementSpec refinement;
};

// The muscle geometry a wrinkle region needs (docs/model.md §6), from a muscle spec: linear R is
// Waters' Rf, phi the zone angle; sheet lines, Ls and Ws as they are. (Here because muscles/
// and wrinkles/ are siblings that do not include each other.)
WrinkleMuscleGeometry WrinkleGeometryOf(const MuscleSpec& muscle);

}  // namespace mimetic
