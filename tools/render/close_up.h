// tools/render/close_up.h: a close-up render and side-by-side panels.
#pragma once

#include <vector>

#include "core/image.h"
#include "geometry/mesh.h"
#include "tools/render/render.h"

namespace mimetic {

// Renders `mesh` as RenderMesh would at `zoom` times `size` pixels (at most 8192) and keeps
// the `size` x `size` window centred on (`focus_x`, `focus_y`), fractions of the full view
// (0, 0 = top left), moved inside the view where it would cross an edge. zoom 1 is the plain
// fitted view. `options.width/height` are ignored.
Image RenderCloseUp(const MeshData& mesh, RenderOptions options, int size, double zoom,
                    double focus_x, double focus_y);

// The images side by side, left to right, with `gap` pixels of `background` between them;
// the height is the tallest image's (shorter ones are centred). Empty input: an empty image.
Image SideBySide(const std::vector<Image>& images, int gap, float3 background);

}  // namespace mimetic
