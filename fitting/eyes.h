// fitting/eyes.h: the eyeballs a head's mesh file carries (the sample head's `eyes` mesh), as
// the spheres the rig's lids slide on (docs/model.md §24, docs/rig-format.md `eyes`).
#pragma once

#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "rig/offline/rig_spec.h"

namespace mimetic {

// The band of skin that slides on an eyeball, as fractions of its radius: weight 1 within
// kEyeBandInner R of the surface, 0 beyond kEyeBandOuter R (2 and 8 mm on a 12 mm eyeball: the
// lids and their inner rolls, not the brow or the cheek).
inline constexpr float kEyeBandInner = 1.f / 6.f;
inline constexpr float kEyeBandOuter = 2.f / 3.f;

// One sphere per connected part of `eyes` (triangles sharing a vertex index), in the order of
// each part's first vertex: the least-squares sphere through the part's vertices (|x|^2 = 2 c.x
// + k, solved in double; radius sqrt(k + |c|^2)). False, with `error` saying which part and
// why, for a mesh without triangles, a part of fewer than 4 vertices or one whose vertices do
// not span a sphere (coplanar, or not finite).
bool FitEyeballs(const MeshData& eyes, std::vector<EyeSphere>* out, std::string* error);

// The rig's `eyes` block for these spheres: band [kEyeBandInner, kEyeBandOuter] times their mean
// radius.
EyesSpec MakeEyesSpec(const std::vector<EyeSphere>& spheres);

}  // namespace mimetic
