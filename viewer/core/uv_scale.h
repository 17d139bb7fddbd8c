// viewer/core/uv_scale.h: how many mesh units one unit of texture space is, over texture space,
// so the UV curve editor can draw a curve wrinkle's width (mesh units) in uv.
//
// The curve-wrinkle builder converts a uv distance to mesh units with a point's isotropic
// texture-to-mesh scale sqrt(sum of its triangles' 3D areas / sum of their uv areas)
// (wrinkles/offline/wrinkle_builder.h, docs/model.md §7). This grid holds the same ratio per
// cell of texture space, from the triangles whose uv centroid falls in the cell (cells with no
// triangle: the whole mesh's ratio), so width_uv = width / At(uv).
#pragma once

#include <vector>

#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic::viewer {

struct UvScaleGrid {
  int cells = 0;              // per side, over [0, 1]^2
  std::vector<float> scale;   // cells * cells, row-major (v rows, u columns); mesh units per uv
  float whole = 0.f;          // the whole mesh's ratio (0: no triangle with uv area)
  // The cell's ratio at `uv` (clamped into [0, 1]^2); `whole` without cells.
  float At(float2 uv) const;
};

// `cells` per side (clamped to [1, 1024]); a mesh without uvs gives an empty grid (At = 0).
UvScaleGrid MakeUvScaleGrid(const MeshData& mesh, int cells = 64);

}  // namespace mimetic::viewer
