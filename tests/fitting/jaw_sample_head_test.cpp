// The jaw on the sample head (issue 13 part 2; docs/model.md §18): the committed default rig
// (assets/head/sample_head.rig.json, fitted from the default template, so it carries the
// template's jaw block) opens the mouth through the lips' slit (content/sample_head.cpp): the
// lips part further the further the jaw opens, and no triangle turns over at the full opening
// with every skin layer and the fold limiter on. The ICT-FaceKit counterpart is jaw_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "content/sample_head.h"
#include "io/landmarks_file.h"
#include "io/rig_loader.h"
#include "jaw_checks.h"
#include "rig/offline/rig_builder.h"
#include "sample_rig.h"
#include "test_support.h"

namespace mimetic {
namespace {

class JawOnSampleHead : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    head_ = new LoadedRig;
    Diagnostics diag;
    EXPECT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", head_, &diag))
        << diag.Format();
    landmarks_ = new Landmarks;
    EXPECT_TRUE(LoadLandmarks(test::SourceDir() + "/assets/head/sample_head.landmarks.json",
                              landmarks_, &diag))
        << diag.Format();
  }
  static void TearDownTestSuite() {
    delete head_;
    delete landmarks_;
    head_ = nullptr, landmarks_ = nullptr;
  }
  void SetUp() override {
    ASSERT_FALSE(head_->rig.jaw().empty())
        << "assets/head/sample_head.rig.json has no jaw: rerun mimetic fit (assets/head/README.md)";
    ASSERT_EQ(landmarks_->points.size(), 68u);
  }
  static const Rig& rig() { return head_->rig; }
  static LoadedRig* head_;
  static Landmarks* landmarks_;
};
LoadedRig* JawOnSampleHead::head_ = nullptr;
Landmarks* JawOnSampleHead::landmarks_ = nullptr;

// The lips near the mouth centre (the midpoint of the inner-lip landmarks 62 and 66, which sit
// on either side of the slit): the head's own vertices (RestMesh lists them first) within
// 12 mm of it and 15 mm of the midline. The slit cuts them into two pieces (the lips meet only
// at the corners, 26 mm out): the upper lip is the piece that holds the vertex nearest the
// upper lip's top (landmark 51), the lower lip the one nearest its bottom (57). At rest the
// slit's two sides are its width apart; the lower lip follows the jaw (weight 1 between the
// mouth corners), the upper lip stays (weight 0), so at the full opening the lips are about the
// jaw's glide |T| apart (its turn is under 2 degrees).
TEST_F(JawOnSampleHead, TheLipsSeparateAsTheJawOpens) {
  const float3 mouth = (landmarks_->points[62] + landmarks_->points[66]) * 0.5f;
  const MeshData rest = RestMesh(rig());
  const uint32_t nv = uint32_t(head_->mesh.vertex_count());
  std::vector<char> in(nv, 0);
  for (uint32_t v = 0; v < nv; ++v) {
    const float3 p = rest.positions[v];
    in[v] = Length(p - mouth) <= 12.f && std::fabs(p.x) <= 15.f;
  }
  // Connected pieces of the region (union-find over the mesh file's triangles).
  std::vector<uint32_t> root(nv);
  for (uint32_t v = 0; v < nv; ++v) root[v] = v;
  auto find = [&](uint32_t v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  const std::vector<uint32_t>& tri = head_->mesh.indices;
  for (size_t t = 0; t < tri.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[t + k], b = tri[t + (k + 1) % 3];
      if (in[a] && in[b]) root[find(a)] = find(b);
    }
  auto nearest = [&](float3 q) {
    uint32_t best = 0;
    for (uint32_t v = 0; v < nv; ++v)
      if (in[v] && (!in[best] || Length(rest.positions[v] - q) < Length(rest.positions[best] - q)))
        best = v;
    return best;
  };
  const uint32_t top = find(nearest(landmarks_->points[51]));
  const uint32_t bottom = find(nearest(landmarks_->points[57]));
  ASSERT_NE(top, bottom) << "the lips are one piece near the mouth centre: no slit";
  std::vector<uint32_t> upper, lower;
  for (uint32_t v = 0; v < nv; ++v) {
    if (!in[v]) continue;
    const uint32_t r = find(v);
    EXPECT_TRUE(r == top || r == bottom) << "vertex " << v << " is on neither lip";
    (r == top ? upper : lower).push_back(v);
  }
  ASSERT_GT(upper.size(), 20u);
  ASSERT_GT(lower.size(), 20u);
  auto gap = [&](float jaw) { return test::SmallestDistance(test::PosedAtJaw(rig(), jaw), upper, lower); };
  float last = gap(0.f);
  EXPECT_NEAR(last, kSampleHeadSlitWidth, 0.01f) << "at rest the lips are the slit's width apart";
  EXPECT_LT(last, 1.f);
  std::printf("sample head lip gap (mm): jaw 0 %.3f", last);
  for (float jaw : {0.25f, 0.5f, 0.75f, 1.f}) {
    const float g = gap(jaw);
    std::printf(", %.2f %.3f", jaw, g);
    EXPECT_GT(g, last + 1.f) << "jaw " << jaw;
    last = g;
  }
  const float glide = Length(rig().jaw().translation);
  std::printf("; the jaw's glide %.3f\n", glide);
  EXPECT_GT(last, 0.5f * glide);
  EXPECT_LT(last, glide + 5.f);
}

// No triangle of the refined mesh turns over at half and at the full opening (every skin layer
// and the fold limiter on; the criterion of tests/fitting/foldover_test.cpp), the mouth corners
// included: there the slit ends, and the jaw weight's lip side term fades out before each
// corner (docs/model.md §18, corner_fade), so the weight is one smooth field around the corner
// (without the fade, 44 and 62 small refined triangles by the corners turned over).
TEST_F(JawOnSampleHead, NoTriangleTurnsOverAtHalfOrTheFullOpening) {
  const MeshData rest = RestMesh(rig());
  for (float jaw : {0.5f, 1.f}) {
    const test::TurnedOver over = test::CountTurnedOver(rest, test::PosedAtJaw(rig(), jaw));
    const float3 at = rest.positions[rest.indices[3 * over.first]];
    EXPECT_EQ(over.count, 0u) << "jaw " << jaw << ": first turned-over triangle " << over.first
                              << " at (" << at.x << ", " << at.y << ", " << at.z << ") mm";
  }
  // The same rig without the fade: triangles by the corners turn over at the full opening.
  LoadedRig no_fade;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(test::EditedSampleRig("no_fade", [](nlohmann::json& j) { j["jaw"]["corner_fade"] = 0; }),
                      &no_fade, &diag))
      << diag.Format();
  EXPECT_GT(test::CountTurnedOver(RestMesh(no_fade.rig), test::PosedAtJaw(no_fade.rig, 1.f)).count, 0u);
}

// The lips carry no fat (docs/model.md §18, the mouth's free edge): the thickness layer's
// bulge of the skin the opening jaw compresses by each mouth corner pushed the inner lip roll
// through the cheek's skin (197 pairs of triangles passing through each other within 14 mm of
// each corner at jaw 0.6; the renders showed dark shards there). With the thickness faded in
// over 0.3 of the mouth width from the slit's edge no triangle passes through another there, at
// half, 0.6 and the full opening, with every skin layer; with the fade off they do, and with
// the thickness layer off they do not.
TEST_F(JawOnSampleHead, TheMouthCornersDoNotPassThroughThemselves) {
  const MeshData rest = RestMesh(rig());
  const float3 corners[2] = {landmarks_->points[48], landmarks_->points[54]};
  for (float jaw : {0.5f, 0.6f, 1.f}) {
    const std::vector<float3> posed = test::PosedAtJaw(rig(), jaw);
    for (const float3& c : corners)
      EXPECT_EQ(test::CountPiercingPairs(rest, posed, c, 14.f), 0u)
          << "jaw " << jaw << ", corner at (" << c.x << ", " << c.y << ", " << c.z << ") mm";
  }
  SkinLayers no_thickness;
  no_thickness.thickness = false;
  const std::vector<float3> bare = test::PosedAtJaw(rig(), 0.6f, no_thickness);
  EXPECT_EQ(test::CountPiercingPairs(rest, bare, corners[0], 14.f), 0u);
  LoadedRig no_fade;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(test::EditedSampleRig("no_thickness_fade",
                                            [](nlohmann::json& j) { j["jaw"]["thickness_fade"] = 0; }),
                      &no_fade, &diag))
      << diag.Format();
  const std::vector<float3> folded = test::PosedAtJaw(no_fade.rig, 0.6f);
  for (const float3& c : corners)
    EXPECT_GT(test::CountPiercingPairs(RestMesh(no_fade.rig), folded, c, 14.f), 20u);
}

}  // namespace
}  // namespace mimetic
