// Overlay colour maps, ranges, legends and values (viewer/core/overlays.h), against numbers
// computed by hand.
#include "viewer/core/overlays.h"

#include <cmath>

#include <gtest/gtest.h>

namespace mimetic::viewer {
namespace {

void ExpectColor(const float3& c, const float3& e) {
  EXPECT_NEAR(c.x, e.x, 1e-6f);
  EXPECT_NEAR(c.y, e.y, 1e-6f);
  EXPECT_NEAR(c.z, e.z, 1e-6f);
}

TEST(ViewerOverlays, ColorMapEndpointsAndMidpoints) {
  ExpectColor(MapColor(ColorMap::kSequential, 0.f), kSequentialStops[0]);
  ExpectColor(MapColor(ColorMap::kSequential, 1.f), kSequentialStops[4]);
  ExpectColor(MapColor(ColorMap::kSequential, 0.5f), kSequentialStops[2]);
  ExpectColor(MapColor(ColorMap::kDiverging, 0.f), kDivergingStops[0]);
  ExpectColor(MapColor(ColorMap::kDiverging, 0.5f), kDivergingStops[1]);
  ExpectColor(MapColor(ColorMap::kDiverging, 1.f), kDivergingStops[2]);
  // Halfway between stops 0 and 1 of the diverging map: their mean.
  const float3 q = MapColor(ColorMap::kDiverging, 0.25f);
  ExpectColor(q, 0.5f * (kDivergingStops[0] + kDivergingStops[1]));
  // Out of range and NaN clamp.
  ExpectColor(MapColor(ColorMap::kSequential, 7.f), kSequentialStops[4]);
  ExpectColor(MapColor(ColorMap::kSequential, NAN), kSequentialStops[0]);
}

TEST(ViewerOverlays, SignedFieldsAreSymmetricAboutTheirNeutralValue) {
  OverlayField f;
  f.overlay = Overlay::kAreaRatio;  // neutral 1
  f.values = {0.8f, 1.f, 1.1f, NAN};
  FitOverlayRange(&f);
  EXPECT_EQ(f.map, ColorMap::kDiverging);
  EXPECT_NEAR(f.lo, 0.8f, 1e-6f);  // 1 - max(|0.8 - 1|, |1.1 - 1|)
  EXPECT_NEAR(f.hi, 1.2f, 1e-6f);
  EXPECT_FLOAT_EQ(f.min_value, 0.8f);
  EXPECT_FLOAT_EQ(f.max_value, 1.1f);
  EXPECT_NEAR(OverlayT(f, 1.f), 0.5f, 1e-6f);  // r = 1 is white
  EXPECT_NEAR(OverlayT(f, 1.1f), 0.75f, 1e-5f);

  OverlayField d;
  d.overlay = Overlay::kDisplacement;
  d.values = {0.f, 2.f, 4.f};
  FitOverlayRange(&d);
  EXPECT_EQ(d.map, ColorMap::kSequential);
  EXPECT_FLOAT_EQ(d.lo, 0.f);
  EXPECT_FLOAT_EQ(d.hi, 4.f);
  const std::vector<LegendEntry> legend = OverlayLegend(d, 5);
  ASSERT_EQ(legend.size(), 5u);
  EXPECT_FLOAT_EQ(legend[1].value, 1.f);
  EXPECT_FLOAT_EQ(legend[4].value, 4.f);
  ExpectColor(legend[0].color, kSequentialStops[0]);
  ExpectColor(legend[4].color, kSequentialStops[4]);
  std::vector<float3> colors;
  OverlayColors(d, &colors);
  ASSERT_EQ(colors.size(), 3u);
  ExpectColor(colors[1], kSequentialStops[2]);
}

TEST(ViewerOverlays, ValuesPerVertexFromTheFrame) {
  const std::vector<uint32_t> vertex_points = {0, 1, 1};
  const std::vector<float3> rest = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  const std::vector<float3> posed = {{3, 4, 0}, {1, 0, 2}, {1, 0, 0}};
  const std::vector<float3> normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  const std::vector<float3> unwrinkled = {{3, 4, 0.5f}, {1, 0, 2.25f}, {1, 0, 0}};
  const std::vector<float> tension = {0.9f, 0.1f, 1.2f, 0.f, 1.2f, 0.f};
  const std::vector<float> thickness = {3.f, 5.f};
  OverlayInputs in;
  in.vertex_points = vertex_points;
  in.rest_positions = rest;
  in.positions = posed;
  in.normals = normals;
  in.unwrinkled = unwrinkled;
  in.tension = tension;
  in.point_thickness = thickness;
  OverlayField f;
  ASSERT_TRUE(ComputeOverlayValues(Overlay::kDisplacement, in, &f));
  EXPECT_EQ(f.values, (std::vector<float>{5.f, 2.f, 0.f}));
  ASSERT_TRUE(ComputeOverlayValues(Overlay::kWrinkle, in, &f));
  EXPECT_EQ(f.values, (std::vector<float>{-0.5f, -0.25f, 0.f}));
  ASSERT_TRUE(ComputeOverlayValues(Overlay::kAreaRatio, in, &f));
  EXPECT_EQ(f.values, (std::vector<float>{0.9f, 1.2f, 1.2f}));
  ASSERT_TRUE(ComputeOverlayValues(Overlay::kCompression, in, &f));
  EXPECT_EQ(f.values, (std::vector<float>{0.1f, 0.f, 0.f}));
  ASSERT_TRUE(ComputeOverlayValues(Overlay::kThickness, in, &f));
  EXPECT_EQ(f.values, (std::vector<float>{3.f, 5.f, 5.f}));
  // The value under the cursor: barycentric weights (0.5, 0.25, 0.25).
  EXPECT_FLOAT_EQ(InterpolateValue(f, 0, 1, 2, 0.25f, 0.25f), 4.f);
  // A span too small is refused, the field untouched.
  in.point_shrinkage = span<const float>(thickness.data(), 1);  // point 1 missing
  EXPECT_FALSE(ComputeOverlayValues(Overlay::kShrinkage, in, &f));
  EXPECT_EQ(f.overlay, Overlay::kThickness);
}

TEST(ViewerOverlays, PointShrinkageIsTheMeanOfTheEntries) {
  // Rows: point 2 with entries {0.2, 0.4}, point 0 with {-0.1}; point 1 has none.
  const std::vector<uint32_t> rows = {2, 0}, offsets = {0, 2, 3};
  const std::vector<float> s = {0.2f, 0.4f, -0.1f};
  std::vector<float> out;
  PointShrinkage(3, rows, offsets, s, &out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_FLOAT_EQ(out[0], -0.1f);
  EXPECT_FLOAT_EQ(out[1], 0.f);
  EXPECT_NEAR(out[2], 0.3f, 1e-7f);
}

TEST(ViewerOverlays, NamesRoundTrip) {
  for (int i = 0; i < kOverlayCount; ++i) {
    Overlay o = Overlay::kNone;
    ASSERT_TRUE(ParseOverlay(OverlayName(Overlay(i)), &o));
    EXPECT_EQ(int(o), i);
  }
  Overlay o = Overlay::kWrinkle;
  EXPECT_FALSE(ParseOverlay("ratio", &o));
  EXPECT_EQ(o, Overlay::kWrinkle);
}

}  // namespace
}  // namespace mimetic::viewer
