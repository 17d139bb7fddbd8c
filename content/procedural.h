// content/procedural.h: procedural test surfaces and rigs (tests, benchmark, README demo
// before a head exists).
#pragma once

#include <cstdint>

#include "geometry/mesh.h"
#include "rig/offline/rig_spec.h"

namespace mimetic {

// A rectangular sheet of `columns` x `rows` vertices spanning [-width/2, width/2] in x and
// [-height/2, height/2] in y, bulged toward +Z like a cheek: z = bulge * (1 - (2x/width)^2)
// * (1 - (2y/height)^2). Triangles face +Z (counter-clockwise seen from +Z); uv = (x/width +
// 0.5, 0.5 - y/height), so v = 0 is the top row as in glTF. No seams.
MeshData MakeSurfaceMesh(uint32_t columns, uint32_t rows, float width, float height, float bulge);

// `count` muscles spread over that surface, alternating linear and sheet, each reaching about
// `coverage` (0..1) of the sheet's area, with strength `strength` (mesh units). For benchmarks
// and tests; names are "muscle_00", "muscle_01", ...
RigSpec MakeSurfaceRigSpec(uint32_t count, float width, float height, float bulge, float coverage,
                           float strength);

// Turns on every skin layer of a MakeSurfaceRigSpec rig, so that every table and file section
// has entries: thickness 3 (mesh units), a wrinkle region on every muscle (`lambda_w`, three
// furrows), three curve wrinkles across the sheet of width `curve_width` (one of each
// profile, area and directional modulation), refinement off (to stay small).
void AddEverySkinLayer(RigSpec* spec, float lambda_w = 0.3f, float curve_width = 4.f);

}  // namespace mimetic
