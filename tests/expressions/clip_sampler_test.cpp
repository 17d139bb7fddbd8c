// tests/expressions/clip_sampler_test.cpp: the clip builder (expressions/offline/clip_builder.h)
// and the sampling job (expressions/runtime/clip_sample_job.h), against values computed here
// from the formulas of docs/expressions.md: the linear midpoint, the Hermite basis, the
// tangent rules, the layers, the end rules; no overshoot on adversarial keys; random seeking
// and sequential playback give the same bits; Run() allocates nothing; the validity table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "alloc_counter.h"
#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_sample_job.h"

namespace mimetic {
namespace {

const std::vector<std::string> kMuscles = {"a", "b", "c"};

ClipKeySpec Key(float t, float v, KeyInterp interp = KeyInterp::kLinear,
                KeyTangent tangent = KeyTangent::kAuto) {
  return {t, v, interp, tangent};
}

ClipChannelSpec Muscle(std::string name, std::vector<ClipKeySpec> keys) {
  return {ClipChannelKind::kMuscle, std::move(name), ClipLayer::kAdd, std::move(keys)};
}

ClipChannelSpec Expr(std::string name, ClipLayer layer, std::vector<ClipKeySpec> keys) {
  return {ClipChannelKind::kExpression, std::move(name), layer, std::move(keys)};
}

CompiledClip Build(std::vector<ClipChannelSpec> channels, ClipEnd end = ClipEnd::kClamp,
                   float duration = -1.f, const std::vector<ClipExpression>& expressions = {},
                   const std::vector<std::string>& muscles = kMuscles) {
  ClipSpec spec{"test", duration, end, std::move(channels)};
  CompiledClip clip;
  Diagnostics diag;
  EXPECT_TRUE(BuildClip(spec, muscles, expressions, &clip, &diag)) << diag.Format();
  return clip;
}

std::vector<float> Sample(const CompiledClip& clip, float t) {
  std::vector<float> out(clip.muscle_count(), -1.f);
  ClipSampleJob job{&clip, t, out, {}};
  EXPECT_TRUE(job.Run());
  return out;
}

// The Hermite basis, in double, written out here from docs/expressions.md.
double Hermite(double t0, double v0, double m0, double t1, double v1, double m1, double t) {
  const double h = t1 - t0, s = (t - t0) / h;
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
  const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  return h00 * v0 + h10 * h * m0 + h01 * v1 + h11 * h * m1;
}

TEST(ClipSampler, LinearIsTheStraightLineBetweenKeys) {
  const CompiledClip clip = Build({Muscle("a", {Key(0, 0.2f), Key(2, 0.8f)})});
  EXPECT_NEAR(Sample(clip, 1.f)[0], 0.5, 1e-7);     // (0.2 + 0.8) / 2
  EXPECT_NEAR(Sample(clip, 0.5f)[0], 0.35, 1e-7);   // 0.2 + 0.25 * 0.6
  EXPECT_EQ(Sample(clip, 0.f)[0], 0.2f);
  EXPECT_EQ(Sample(clip, 2.f)[0], 0.8f);
  // Muscles without a channel stay 0.
  EXPECT_EQ(Sample(clip, 1.f)[1], 0.f);
  EXPECT_EQ(Sample(clip, 1.f)[2], 0.f);
}

TEST(ClipSampler, StepHoldsUntilTheNextKey) {
  const CompiledClip clip =
      Build({Muscle("b", {Key(0, 0.3f, KeyInterp::kStep), Key(1, 0.9f, KeyInterp::kStep),
                          Key(2, 0.1f)})});
  EXPECT_EQ(Sample(clip, 0.f)[1], 0.3f);
  EXPECT_EQ(Sample(clip, 0.999f)[1], 0.3f);
  EXPECT_EQ(Sample(clip, 1.f)[1], 0.9f);
  EXPECT_EQ(Sample(clip, 1.5f)[1], 0.9f);
  EXPECT_EQ(Sample(clip, 2.f)[1], 0.1f);
}

TEST(ClipSampler, BeforeTheFirstKeyItsValueAndAfterTheLastKeyItsValue) {
  // Channel a starts at 1 s; channel b ends at 1 s; the clip lasts 3 s (channel c).
  const CompiledClip clip = Build({Muscle("a", {Key(1, 0.4f), Key(2, 0.6f)}),
                                   Muscle("b", {Key(0, 0.1f), Key(1, 0.7f)}),
                                   Muscle("c", {Key(0, 0.f), Key(3, 0.3f)})});
  EXPECT_EQ(clip.duration(), 3.f);
  EXPECT_EQ(Sample(clip, 0.5f)[0], 0.4f);
  EXPECT_EQ(Sample(clip, 2.5f)[0], 0.6f);
  EXPECT_EQ(Sample(clip, 2.5f)[1], 0.7f);
}

TEST(ClipSampler, CubicFollowsTheHermiteBasisWithCatmullRomTangents) {
  // Keys (0, 0.1), (1, 0.5), (3, 0.7). Secants d0 = 0.4, d1 = 0.1. Auto tangents: m0 = d0 =
  // 0.4 (<= 3 d0), m1 = (0.7 - 0.1) / 3 = 0.2 (<= 3 min(d0, d1) = 0.3), m2 = d1 = 0.1.
  const CompiledClip clip =
      Build({Muscle("a", {Key(0, 0.1f, KeyInterp::kCubic), Key(1, 0.5f, KeyInterp::kCubic),
                          Key(3, 0.7f)})});
  const auto m = clip.key_tangents();
  EXPECT_NEAR(m[0], 0.4, 1e-7);
  EXPECT_NEAR(m[1], 0.2, 1e-7);
  EXPECT_NEAR(m[2], 0.1, 1e-7);
  EXPECT_NEAR(Sample(clip, 0.3f)[0], Hermite(0, 0.1, 0.4, 1, 0.5, 0.2, 0.3), 2e-7);
  EXPECT_NEAR(Sample(clip, 2.2f)[0], Hermite(1, 0.5, 0.2, 3, 0.7, 0.1, 2.2), 2e-7);
  // s = 0.5 of the first segment: (v0 + v1) / 2 + h (m0 - m1) / 8.
  EXPECT_NEAR(Sample(clip, 0.5f)[0], 0.3 + (0.4 - 0.2) / 8, 2e-7);
}

TEST(ClipSampler, TangentRulesAndTheLimiter) {
  // Keys (0, 0), (1, 0.01), (2, 1): d0 = 0.01, d1 = 0.99.
  std::vector<ClipKeySpec> keys = {Key(0, 0.f), Key(1, 0.01f), Key(2, 1.f)};
  const double d0 = 0.01f, d1 = 1.0 - double(0.01f);
  // auto: Catmull-Rom (1 - 0) / 2 = 0.5, limited to 3 min(d0, d1) = 0.03.
  std::vector<float> m = ClipTangents(keys);
  EXPECT_NEAR(m[0], d0, 1e-9);
  EXPECT_NEAR(m[1], 3 * d0, 1e-8);
  EXPECT_NEAR(m[2], d1, 1e-7);
  // clamped: the weighted harmonic mean (w1 + w2) / (w1 / d0 + w2 / d1), w1 = w2 = 3 (even
  // spacing), and 0 at both ends.
  for (ClipKeySpec& k : keys) k.tangent = KeyTangent::kClamped;
  m = ClipTangents(keys);
  EXPECT_EQ(m[0], 0.f);
  EXPECT_NEAR(m[1], 6.0 / (3.0 / d0 + 3.0 / d1), 1e-8);
  EXPECT_EQ(m[2], 0.f);
  // Uneven spacing: keys at 0, 1, 4 (h0 = 1, h1 = 3): w1 = 2 h1 + h0 = 7, w2 = h1 + 2 h0 = 5.
  keys = {Key(0, 0.f, KeyInterp::kCubic, KeyTangent::kClamped),
          Key(1, 0.3f, KeyInterp::kCubic, KeyTangent::kClamped),
          Key(4, 0.9f, KeyInterp::kCubic, KeyTangent::kClamped)};
  m = ClipTangents(keys);
  const double e0 = double(0.3f), e1 = (double(0.9f) - double(0.3f)) / 3;
  EXPECT_NEAR(m[1], 12.0 / (7.0 / e0 + 5.0 / e1), 1e-7);
  // A local extremum is flat in both modes; so is a key next to an equal value.
  keys = {Key(0, 0.2f), Key(1, 0.8f), Key(2, 0.5f), Key(3, 0.5f), Key(4, 0.9f)};
  m = ClipTangents(keys);
  EXPECT_EQ(m[1], 0.f);
  EXPECT_EQ(m[2], 0.f);
  EXPECT_EQ(m[3], 0.f);
  EXPECT_EQ(ClipTangents({Key(0, 0.5f)})[0], 0.f);
}

// Every sample of a cubic segment lies within its two key values, over a dense grid.
void ExpectNoOvershoot(const std::vector<ClipKeySpec>& keys) {
  const CompiledClip clip = Build({Muscle("a", keys)});
  const float d = clip.duration();
  for (int i = 0; i <= 20000; ++i) {
    const float t = d * float(i) / 20000.f;
    size_t k = 0;
    while (k + 2 < keys.size() && keys[k + 1].t <= t) ++k;
    const float lo = std::min(keys[k].v, keys[k + 1].v), hi = std::max(keys[k].v, keys[k + 1].v);
    const float v = Sample(clip, t)[0];
    ASSERT_GE(v, lo) << "t " << t << " segment " << k;
    ASSERT_LE(v, hi) << "t " << t << " segment " << k;
  }
}

TEST(ClipSampler, CubicNeverOvershootsItsKeys) {
  for (KeyTangent tangent : {KeyTangent::kAuto, KeyTangent::kClamped}) {
    SCOPED_TRACE(int(tangent));
    // Spikes 0, 1, 0, 1 on uneven spacing.
    std::vector<ClipKeySpec> keys;
    const float times[] = {0.f, 0.05f, 1.f, 1.02f, 3.f, 3.1f, 3.15f, 5.f};
    for (int i = 0; i < 8; ++i) keys.push_back(Key(times[i], float(i % 2), KeyInterp::kCubic, tangent));
    ExpectNoOvershoot(keys);
    // A near-plateau after a steep rise: unlimited Catmull-Rom overshoots here (checked below).
    keys = {Key(0, 0.f, KeyInterp::kCubic, tangent), Key(1, 0.95f, KeyInterp::kCubic, tangent),
            Key(1.1f, 1.f, KeyInterp::kCubic, tangent), Key(3, 1.f, KeyInterp::kCubic, tangent)};
    ExpectNoOvershoot(keys);
    // Random keys, seeded.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> gap(0.001f, 1.f), value(0.f, 1.f);
    keys.clear();
    float t = 0.f;
    for (int i = 0; i < 60; ++i, t += gap(rng))
      keys.push_back(Key(t, i % 7 == 3 ? 1.f : value(rng), KeyInterp::kCubic, tangent));
    ExpectNoOvershoot(keys);
  }
  // The cases are adversarial: without the limiter they overshoot. The plateau, with raw
  // Catmull-Rom tangents: m(1.1) = (1 - 0.95) / (3 - 1) = 0.025 on the flat segment from 1.1 s
  // to 3 s (value 1 at both ends) lifts it above 1; the steep rise (0, 0), (1, 0.01), (2, 1):
  // m(1) = (1 - 0) / 2 = 0.5 = 50 times the first secant drives the first segment below 0.
  double peak = 0, dip = 0;
  for (int i = 0; i <= 1000; ++i) {
    peak = std::max(peak, Hermite(1.1, 1, 0.025, 3, 1, 0, 1.1 + 1.9 * i / 1000.0));
    dip = std::min(dip, Hermite(0, 0, 0.01, 1, 0.01, 0.5, i / 1000.0));
  }
  EXPECT_GT(peak, 1.0);
  EXPECT_LT(dip, 0.0);
  ExpectNoOvershoot({Key(0, 0.f, KeyInterp::kCubic), Key(1, 0.01f, KeyInterp::kCubic), Key(2, 1.f)});
}

TEST(ClipSampler, LoopWrapsAndClampHolds) {
  const std::vector<ClipChannelSpec> channels = {
      Muscle("a", {Key(0, 0.f, KeyInterp::kCubic), Key(1, 1.f, KeyInterp::kCubic), Key(2, 0.2f)})};
  const CompiledClip loop = Build(channels, ClipEnd::kLoop);
  const CompiledClip clamp = Build(channels, ClipEnd::kClamp);
  ASSERT_EQ(loop.duration(), 2.f);
  const std::vector<float> at = Sample(loop, 0.25f);
  EXPECT_EQ(Sample(loop, 2.25f), at);       // duration + 0.25
  EXPECT_EQ(Sample(loop, 4.25f), at);
  EXPECT_EQ(Sample(loop, -1.75f), at);      // before 0, wrapped too
  EXPECT_EQ(Sample(loop, 2.f), Sample(loop, 0.f));  // the duration is the next cycle's 0
  EXPECT_EQ(ClipLocalTime(loop, 2.25f), 0.25f);
  EXPECT_EQ(Sample(clamp, 2.25f)[0], 0.2f);   // the last key's value
  EXPECT_EQ(Sample(clamp, 1e9f)[0], 0.2f);
  EXPECT_EQ(Sample(clamp, -3.f)[0], 0.f);     // the first key's value
  EXPECT_EQ(ClipLocalTime(clamp, 7.f), 2.f);
  // A duration past the last key: a loop holds the last key until the duration.
  const CompiledClip longer = Build(channels, ClipEnd::kLoop, 3.f);
  EXPECT_EQ(Sample(longer, 2.5f)[0], 0.2f);
  EXPECT_EQ(Sample(longer, 3.25f), Sample(longer, 0.25f));
}

TEST(ClipSampler, NanTimeIsZeroAndInfinitiesHaveTheirRule) {
  const std::vector<ClipChannelSpec> channels = {Muscle("a", {Key(0, 0.3f), Key(1, 0.9f)})};
  const CompiledClip clamp = Build(channels), loop = Build(channels, ClipEnd::kLoop);
  const float nan = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(Sample(clamp, nan), Sample(clamp, 0.f));
  EXPECT_EQ(Sample(loop, nan), Sample(loop, 0.f));
  EXPECT_EQ(Sample(clamp, inf)[0], 0.9f);
  EXPECT_EQ(Sample(clamp, -inf)[0], 0.3f);
  EXPECT_EQ(Sample(loop, inf), Sample(loop, 0.f));
}

TEST(ClipSampler, LayersAddMaxAndOverrideInChannelOrder) {
  const std::vector<ClipExpression> expressions = {
      {"E1", {{"a", 0.6f}, {"b", 0.2f}}},
      {"E2", {{"a", 0.5f}, {"c", 1.f}}},
  };
  // b = 0.5; + 0.5 E1: a = 0.3, b = 0.6; max with 0.8 E2: a = 0.4, c = 0.8.
  CompiledClip clip = Build({Muscle("b", {Key(0, 0.5f)}), Expr("E1", ClipLayer::kAdd, {Key(0, 0.5f)}),
                             Expr("E2", ClipLayer::kMax, {Key(0, 0.8f)})},
                            ClipEnd::kClamp, 1.f, expressions);
  std::vector<float> a = Sample(clip, 0.5f);
  EXPECT_NEAR(a[0], 0.4, 1e-7);
  EXPECT_NEAR(a[1], 0.6, 1e-7);
  EXPECT_NEAR(a[2], 0.8, 1e-7);
  // Then override with 0.5 E1: a = 0.4 + 0.5 (0.6 - 0.4) = 0.5, b = 0.6 + 0.5 (0.2 - 0.6) =
  // 0.4; c is not E1's, so it stays 0.8.
  clip = Build({Muscle("b", {Key(0, 0.5f)}), Expr("E1", ClipLayer::kAdd, {Key(0, 0.5f)}),
                Expr("E2", ClipLayer::kMax, {Key(0, 0.8f)}),
                Muscle("c", {Key(0, 0.8f)})},
               ClipEnd::kClamp, 1.f, expressions);
  // (the same with c set by a muscle channel after E2: 0.8 either way)
  a = Sample(clip, 0.5f);
  EXPECT_NEAR(a[2], 0.8, 1e-7);
  const std::vector<ClipExpression> with_override = {
      {"E1", {{"a", 0.6f}, {"b", 0.2f}}}, {"E2", {{"a", 0.5f}, {"c", 1.f}}},
      {"E1o", {{"a", 0.6f}, {"b", 0.2f}}}};
  clip = Build({Muscle("b", {Key(0, 0.5f)}), Expr("E1", ClipLayer::kAdd, {Key(0, 0.5f)}),
                Expr("E2", ClipLayer::kMax, {Key(0, 0.8f)}),
                Expr("E1o", ClipLayer::kOverride, {Key(0, 0.5f)})},
               ClipEnd::kClamp, 1.f, with_override);
  a = Sample(clip, 0.5f);
  EXPECT_NEAR(a[0], 0.5, 1e-7);
  EXPECT_NEAR(a[1], 0.4, 1e-7);
  EXPECT_NEAR(a[2], 0.8, 1e-7);
  // Add clamps at 1: a = 0.9 + 1 * 0.5 -> 1. A muscle channel after it sets the value.
  clip = Build({Muscle("a", {Key(0, 0.9f)}), Expr("E2", ClipLayer::kAdd, {Key(0, 1.f)}),
                Muscle("b", {Key(0, 0.25f)})},
               ClipEnd::kClamp, 1.f, expressions);
  a = Sample(clip, 0.f);
  EXPECT_EQ(a[0], 1.f);
  EXPECT_EQ(a[1], 0.25f);
  EXPECT_EQ(a[2], 1.f);
  // A muscle channel after an expression replaces what the expression gave it.
  clip = Build({Expr("E2", ClipLayer::kAdd, {Key(0, 1.f)}), Muscle("a", {Key(0, 0.1f)})},
               ClipEnd::kClamp, 1.f, expressions);
  EXPECT_EQ(Sample(clip, 0.f)[0], 0.1f);
  // Only the expressions the clip uses are compiled.
  EXPECT_EQ(clip.expression_count(), 1u);
}

TEST(ClipSampler, RandomSeekingGivesTheBitsOfSequentialPlayback) {
  std::vector<ClipExpression> expressions;
  std::vector<ClipChannelSpec> channels;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const std::vector<std::string> muscles = {"m0", "m1", "m2", "m3", "m4", "m5"};
  for (int c = 0; c < 8; ++c) {
    std::vector<ClipKeySpec> keys;
    float t = 0.f;
    for (int k = 0; k < 20; ++k, t += 0.05f + unit(rng) * 0.3f)
      keys.push_back(Key(t, unit(rng), KeyInterp(k % 3), KeyTangent(k % 2)));
    if (c < 4) {
      channels.push_back(Muscle(muscles[c], keys));
    } else {
      ClipExpression e{"E" + std::to_string(c), {}};
      for (const std::string& m : muscles) e.activations.push_back({m, unit(rng)});
      expressions.push_back(e);
      channels.push_back(Expr(e.name, ClipLayer(c % 3), keys));
    }
  }
  const CompiledClip clip = Build(channels, ClipEnd::kLoop, -1.f, expressions, muscles);
  const int frames = 400;
  std::vector<float> sequential(frames * muscles.size()), seeked(frames * muscles.size());
  ClipSampleJob job;
  job.clip = &clip;
  for (int f = 0; f < frames; ++f) {
    job.time = float(f) / 60.f;
    job.out_activations = span<float>(&sequential[f * muscles.size()], muscles.size());
    ASSERT_TRUE(job.Run());
  }
  std::vector<int> order(frames);
  for (int f = 0; f < frames; ++f) order[f] = f;
  std::shuffle(order.begin(), order.end(), rng);
  for (int f : order) {
    job.time = float(f) / 60.f;
    job.out_activations = span<float>(&seeked[f * muscles.size()], muscles.size());
    ASSERT_TRUE(job.Run());
  }
  EXPECT_EQ(std::memcmp(sequential.data(), seeked.data(), sequential.size() * sizeof(float)), 0);
  // And backwards.
  for (int f = frames - 1; f >= 0; --f) {
    job.time = float(f) / 60.f;
    job.out_activations = span<float>(&seeked[f * muscles.size()], muscles.size());
    ASSERT_TRUE(job.Run());
  }
  EXPECT_EQ(std::memcmp(sequential.data(), seeked.data(), sequential.size() * sizeof(float)), 0);
  for (float v : sequential) {
    EXPECT_GE(v, 0.f);
    EXPECT_LE(v, 1.f);
  }
}

TEST(ClipSampler, RunAllocatesNothing) {
  const std::vector<ClipExpression> expressions = {{"E", {{"a", 0.5f}, {"c", 1.f}}}};
  const CompiledClip clip =
      Build({Muscle("a", {Key(0, 0.f, KeyInterp::kCubic), Key(1, 1.f), Key(2, 0.f)}),
             Expr("E", ClipLayer::kOverride, {Key(0, 0.f, KeyInterp::kStep), Key(1.5f, 1.f)})},
            ClipEnd::kLoop, -1.f, expressions);
  float out[3];
  ClipSampleJob job{&clip, 0.f, out, {}};
  const long before = g_allocations.load();
  for (int i = 0; i < 1000; ++i) {
    job.time = float(i) * 0.013f;
    ASSERT_TRUE(job.Run());
  }
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(ClipSampler, ValidityTable) {
  const CompiledClip clip = Build({Muscle("a", {Key(0, 0.5f)})});
  const CompiledClip unbuilt;
  float out[4] = {7.f, 7.f, 7.f, 7.f};
  struct Case {
    const char* what;
    const CompiledClip* clip;
    size_t out_size;
    bool valid;
  } cases[] = {
      {"null clip", nullptr, 3, false},
      {"clip never built", &unbuilt, 3, false},
      {"output one short", &clip, 2, false},
      {"output empty", &clip, 0, false},
      {"output exactly #muscles", &clip, 3, true},
      {"output longer", &clip, 4, true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    std::fill(out, out + 4, 7.f);
    ClipSampleJob job{c.clip, 0.f, span<float>(out, c.out_size), {}};
    EXPECT_EQ(job.Validate(), c.valid);
    EXPECT_EQ(job.Run(), c.valid);
    if (!c.valid) {
      for (float v : out) EXPECT_EQ(v, 7.f);  // untouched
    } else {
      EXPECT_EQ(out[0], 0.5f);
      EXPECT_EQ(out[1], 0.f);
      EXPECT_EQ(out[3], 7.f);  // past muscle_count: untouched
    }
  }
  // A NaN time is not a reason to refuse.
  ClipSampleJob job{&clip, std::numeric_limits<float>::quiet_NaN(), span<float>(out, 3), {}};
  EXPECT_TRUE(job.Validate());
}

TEST(ClipBuilder, NameResolvesBothSidesAndCompiledArraysAreFlat) {
  const std::vector<std::string> muscles = {"smile_L", "smile_R", "brow"};
  const CompiledClip clip =
      Build({Muscle("smile", {Key(0, 0.f), Key(1, 0.6f)}), Muscle("brow", {Key(0, 1.f)})},
            ClipEnd::kClamp, -1.f, {}, muscles);
  ASSERT_EQ(clip.channel_count(), 3u);
  EXPECT_EQ(clip.targets()[0], 0u);
  EXPECT_EQ(clip.targets()[1], 1u);
  EXPECT_EQ(clip.targets()[2], 2u);
  EXPECT_EQ(std::vector<uint32_t>(clip.key_offsets().begin(), clip.key_offsets().end()),
            (std::vector<uint32_t>{0, 2, 4, 5}));
  const std::vector<float> a = Sample(clip, 0.5f);
  EXPECT_NEAR(a[0], 0.3, 1e-7);
  EXPECT_EQ(a[0], a[1]);
  EXPECT_EQ(a[2], 1.f);
}

TEST(ClipBuilder, ErrorsNameTheChannelAndTheClosestNames) {
  const std::vector<std::string> muscles = {"smile_L", "smile_R", "frontalis_inner_L"};
  const std::vector<ClipExpression> expressions = {{"mouthSmile_L", {{"smile_L", 1.f}}},
                                                   {"browUp", {{"frontalis_inner_X", 1.f}}},
                                                   {"twice", {}}, {"twice", {}}};
  struct Case {
    std::vector<ClipChannelSpec> channels;
    std::string message;
  } cases[] = {
      {{Muscle("frontalis", {Key(0, 1.f)})},
       "channels[0].muscle: unknown muscle \"frontalis\"; closest: frontalis_inner_L"},
      {{Muscle("smile", {Key(0, 1.f)}), Muscle("smile_R", {Key(0, 1.f)})},
       "channels[1].muscle: \"smile_R\" drives smile_R, already driven by channels[0]"},
      {{Expr("mouthSmile", ClipLayer::kAdd, {Key(0, 1.f)})},
       "channels[0].expression: unknown expression \"mouthSmile\"; closest: mouthSmile_L"},
      {{Expr("browUp", ClipLayer::kAdd, {Key(0, 1.f)})},
       "channels[0].expression: expression \"browUp\": muscle \"frontalis_inner_X\" is not in "
       "the rig; closest: frontalis_inner_L"},
      {{Expr("twice", ClipLayer::kAdd, {Key(0, 1.f)})},
       "channels[0].expression: expression \"twice\" is given 2 times (expressions 2, 3)"},
      {{Muscle("smile_L", {Key(1, 1.f), Key(0.5f, 0.f)})},
       "channels[0].keys[1].t: is 0.5, not after keys[0].t = 1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    ClipSpec spec{"bad", -1.f, ClipEnd::kClamp, c.channels};
    CompiledClip clip;
    Diagnostics diag;
    EXPECT_FALSE(BuildClip(spec, muscles, expressions, &clip, &diag));
    EXPECT_NE(diag.Format().find(c.message), std::string::npos) << diag.Format();
    EXPECT_FALSE(clip.built());
  }
  // No expressions at all: said so.
  ClipSpec spec{"bad", -1.f, ClipEnd::kClamp, {Expr("x", ClipLayer::kAdd, {Key(0, 1.f)})}};
  CompiledClip clip;
  Diagnostics diag;
  EXPECT_FALSE(BuildClip(spec, muscles, {}, &clip, &diag));
  EXPECT_NE(diag.Format().find("unknown expression \"x\" (no expressions were given)"),
            std::string::npos) << diag.Format();
}


// The jaw ("jaw" where a muscle name goes, clip.h kJawInputName): a jaw channel sets it, an
// expression that names it combines it by the channel's layer, like a muscle; out_jaw gets it.
float SampleJaw(const CompiledClip& clip, float t, std::vector<float>* activations = nullptr) {
  std::vector<float> out(clip.muscle_count(), -1.f);
  float jaw = -1.f;
  ClipSampleJob job{&clip, t, out, span<float>(&jaw, 1)};
  EXPECT_TRUE(job.Run());
  if (activations) *activations = out;
  return jaw;
}

TEST(ClipSampler, TheJawIsOneMoreValueUnderTheSameRules) {
  // A jaw channel, linear 0 -> 0.8 over 2 s, beside a muscle channel.
  const CompiledClip direct =
      Build({Muscle("jaw", {Key(0, 0.f), Key(2, 0.8f)}), Muscle("a", {Key(0, 0.5f)})});
  EXPECT_TRUE(direct.animates_jaw());
  std::vector<float> a;
  EXPECT_NEAR(SampleJaw(direct, 1.f, &a), 0.4, 1e-7);
  EXPECT_EQ(a[0], 0.5f);
  EXPECT_EQ(a[1], 0.f);
  // Without out_jaw the job still runs and writes the activations only.
  EXPECT_EQ(Sample(direct, 1.f)[0], 0.5f);
  // Expressions: Open {jaw 0.6, a 0.2}, Wide {jaw 0.9}; jaw channel first at 0.3.
  const std::vector<ClipExpression> ex = {{"Open", {{"jaw", 0.6f}, {"a", 0.2f}}},
                                          {"Wide", {{"jaw", 0.9f}}},
                                          {"Still", {{"b", 1.f}}}};
  auto with = [&](ClipLayer layer, const char* name, float w) {
    return Build({Muscle("jaw", {Key(0, 0.3f)}), Expr(name, layer, {Key(0, w)})},
                 ClipEnd::kClamp, -1.f, ex);
  };
  EXPECT_NEAR(SampleJaw(with(ClipLayer::kAdd, "Open", 0.5f), 0.f), 0.3 + 0.5 * 0.6, 1e-7);
  EXPECT_EQ(SampleJaw(with(ClipLayer::kAdd, "Wide", 1.f), 0.f), 1.f);  // 0.3 + 0.9, clamped
  EXPECT_NEAR(SampleJaw(with(ClipLayer::kMax, "Open", 0.5f), 0.f), 0.3, 1e-7);   // max(.3, .3)
  EXPECT_NEAR(SampleJaw(with(ClipLayer::kMax, "Wide", 0.5f), 0.f), 0.45, 1e-7);  // max(.3, .45)
  EXPECT_NEAR(SampleJaw(with(ClipLayer::kOverride, "Wide", 0.5f), 0.f), 0.3 + 0.5 * (0.9 - 0.3),
              1e-7);
  // An override expression that does not name the jaw leaves it; add and max add 0.
  EXPECT_NEAR(SampleJaw(with(ClipLayer::kOverride, "Still", 1.f), 0.f), 0.3, 1e-7);
  EXPECT_NEAR(SampleJaw(with(ClipLayer::kAdd, "Still", 1.f), 0.f), 0.3, 1e-7);
  // A clip that never names the jaw gives 0 and says so.
  const CompiledClip none = Build({Muscle("a", {Key(0, 0.5f)})});
  EXPECT_FALSE(none.animates_jaw());
  EXPECT_EQ(SampleJaw(none, 0.f), 0.f);
  // Two jaw channels are refused with both channels named (CheckClipSpec).
  ClipSpec twice{"t", -1.f, ClipEnd::kClamp,
                 {Muscle("jaw", {Key(0, 0.1f)}), Muscle("jaw", {Key(0, 0.2f)})}};
  CompiledClip clip;
  Diagnostics diag;
  EXPECT_FALSE(BuildClip(twice, kMuscles, {}, &clip, &diag));
  EXPECT_TRUE(diag.Contains("channels[1].muscle")) << diag.Format();
  EXPECT_TRUE(diag.Contains("\"jaw\" is already the target of channels[0]")) << diag.Format();
  // A rig with a muscle named "jaw" keeps it a muscle.
  const CompiledClip muscle = Build({Muscle("jaw", {Key(0, 0.7f)})}, ClipEnd::kClamp, -1.f, {},
                                    {"a", "jaw"});
  EXPECT_FALSE(muscle.animates_jaw());
  EXPECT_EQ(Sample(muscle, 0.f)[1], 0.7f);
}

}  // namespace
}  // namespace mimetic
