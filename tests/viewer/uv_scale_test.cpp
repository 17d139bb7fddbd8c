// viewer/core/uv_scale.h: the texture-to-mesh scale per cell of texture space, from areas.
#include "viewer/core/uv_scale.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mimetic::viewer {
namespace {

// Two unit squares of uv side by side ([0, 0.5] and [0.5, 1] in u, [0, 1] in v) mapped onto
// 3D rectangles 10 x 20 (scales sqrt(200 / 0.5) = 20) and 30 x 20 (sqrt(600 / 0.5) = 34.64).
MeshData TwoPanels() {
  MeshData m;
  m.positions = {{0, 0, 0}, {10, 0, 0}, {10, 20, 0}, {0, 20, 0},
                 {10, 0, 0}, {40, 0, 0}, {40, 20, 0}, {10, 20, 0}};
  m.uvs = {{0, 0}, {0.5f, 0}, {0.5f, 1}, {0, 1}, {0.5f, 0}, {1, 0}, {1, 1}, {0.5f, 1}};
  m.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  return m;
}

TEST(UvScaleGrid, IsTheSquareRootOfTheAreaRatioInEachCell) {
  const UvScaleGrid g = MakeUvScaleGrid(TwoPanels(), 2);
  ASSERT_EQ(g.cells, 2);
  // Triangle centroids: (1/3, 1/3), (1/6, 2/3) on the left; (5/6, 1/3), (2/3, 2/3) on the right.
  EXPECT_NEAR(g.At({0.2f, 0.2f}), 20.f, 1e-4f);
  EXPECT_NEAR(g.At({0.2f, 0.9f}), 20.f, 1e-4f);
  EXPECT_NEAR(g.At({0.9f, 0.2f}), std::sqrt(1200.f), 1e-3f);
  EXPECT_NEAR(g.At({0.9f, 0.9f}), std::sqrt(1200.f), 1e-3f);
  EXPECT_NEAR(g.whole, std::sqrt(800.f / 1.f), 1e-3f);  // all 3D area over all uv area
  EXPECT_NEAR(g.At({-5.f, 7.f}), 20.f, 1e-4f);           // clamped into the square
}

TEST(UvScaleGrid, EmptyCellsTakeTheWholeMeshsRatioAndNoUvsGiveNothing) {
  const UvScaleGrid g = MakeUvScaleGrid(TwoPanels(), 8);
  EXPECT_EQ(g.At({0.99f, 0.01f}), g.whole);  // no centroid in that corner cell
  MeshData bare = TwoPanels();
  bare.uvs.clear();
  EXPECT_EQ(MakeUvScaleGrid(bare).At({0.5f, 0.5f}), 0.f);
}

}  // namespace
}  // namespace mimetic::viewer
