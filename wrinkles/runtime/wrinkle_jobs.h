// wrinkles/runtime/wrinkle_jobs.h: large-scale wrinkle displacement along the normal
// (docs/model.md §6-8): muscle-derived wrinkles (Zhang et al. 2005) and curve wrinkles (Bando et al.
// 2002/2003, with the Yang-Zhang 2005 profile as an alternative). Job conventions: see
// strain_jobs.h. Both jobs ADD to `positions` (X3 = X2 + sum W N1, docs/model.md §1 step 4); rows of
// one table name distinct points, so a row range split across threads is safe and bit-identical,
// but two tables that share points must run one after the other (in a fixed order).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/math.h"
#include "core/span.h"
#include "wrinkles/runtime/profiles.h"

namespace mimetic {

// Muscle-derived wrinkles of one muscle (docs/model.md §6, 001 eq. 4-8, 11-12, 15) over its
// wrinkling region, whose rows (points, phase w_i, attenuation At_i) were fixed on the REST
// pose when the rig was compiled (BuildMuscleWrinkleTable in wrinkles/offline):
//   W_i = H(w_i) * A(eps_i) * At_i,   x_i += W_i N_i.
// **choice** (how activation enters): 001 drives the amplitude by the compression eps alone
// (EdgeCompressionJob over the same rows), so there is no separate activation factor: at rest
// eps = 0 and A(0) = 0, so wrinkles vanish without any gate and grow continuously with the
// compression whichever muscles cause it. A caller may skip the job for speed only where it
// knows eps <= 0 on every row. A rig may add a gate by the muscle's own activation (`gate`, a
// second **choice**, docs/model.md §6): W_i times G, G = WrinkleGate(a, gate) in [0, 1].
struct MuscleWrinkleJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> normals;        // N1, unit normals per point; every index used must exist
  span<const uint32_t> points;       // region point of each row; >= end
  span<const float> phase;           // w_i in [0, 2u] (001 eq. 7), mesh units; >= end
  span<const float> attenuation;     // At_i in [0, 1] (001 eq. 12 / 15); >= end
  span<const float> compression;     // eps_i per row (EdgeCompressionJob); >= end
  float half_cycle = 0.f;            // u = (1 - lambda_w) R / (2 n_w) (001 eq. 6), mesh units,
                                     // > 0; Validate refuses <= 0
  float furrow_depth = 0.f;          // k0 (001 eq. 5), mesh units, >= 0
  float shape = 0.f;                 // alpha (001 eq. 5), shape modulation, finite
  size_t begin = 0;                  // first row
  size_t end = 0;                    // one past the last row
  span<float3> positions;            // points, in/out (+= W N); every index used must exist
  span<float> out_amplitudes;        // optional: W_i per row for overlays; empty or >= end
  // Optional: H(w_i) At_i per row, precomputed (both are fixed on the rest pose; the rig
  // builder stores them). When non-empty (>= end), phase, attenuation, half_cycle,
  // furrow_depth and shape are not read and W_i = profile_i A(eps_i): no pow() per frame.
  span<const float> profile;
  float gate = 1.f;                  // G in [0, 1] (WrinkleGate of the muscle's activation), a
                                     // factor on every row's W; 1 = no gate; Validate refuses
                                     // a value outside [0, 1] or NaN
};

// H(w_i) At_i for one region row (001 eq. 5 and 12/15): the per-row constant of
// MuscleWrinkleJob's fast path, computed exactly as its general path does.
float MuscleWrinkleProfile(float phase, float half_cycle, float furrow_depth, float shape,
                           float attenuation);

// Cross-section of a curve wrinkle.
enum class CurveWrinkleProfile : uint32_t {
  kBando = 0,           // S(l) = d (l/w - 1) exp(-l/w) (000 eq. 2) times the modulation
  kYangZhang = 1,       // Yang-Zhang f (004 eq. 1-2), depth by eq. 9
  kYangZhangExact = 2,  // Yang-Zhang f, depth by the Newton solve of eq. 6 (YangZhangSpan::kFlank)
};

// Which strain drives a curve wrinkle.
enum class CurveWrinkleModulation : uint32_t {
  kDirectional = 0,  // shrinkage s across the curve (000 eq. 4-5): M(s, r)
  kArea = 1,         // area ratio r of the point (002 eq. 1, 6): C(r, k_r)
};

// Run-time parameters of one curve wrinkle (built from CurveWrinkleSpec by the offline
// builder). All lengths in mesh units: the builder converts texture-space distances to mesh
// units with the local texture-to-mesh scale.
// Bando: W = S(l; depth, width) * (M(s; rest_amplitude) or C(r; rest_amplitude)).
// Yang-Zhang: the skin length ratio across the furrow is S = 1 - s (directional) or S = r
//   (area, **choice**: the area change is taken as compression across the furrow), a = S a0,
//   h from eq. 9 (or exactly), W = f(l; a, h); no extra modulation factor (the profile already
//   animates with S; `rest_amplitude` is unused).
struct CurveWrinkleParams {
  CurveWrinkleProfile profile = CurveWrinkleProfile::kBando;
  CurveWrinkleModulation modulation = CurveWrinkleModulation::kDirectional;
  float depth = 0.f;           // d (Bando) or rest depth h0 (Yang-Zhang), mesh units, >= 0
  float width = 0.f;           // w (Bando) or rest half width a0 (Yang-Zhang), mesh units, > 0
  float rest_amplitude = 0.f;  // r of 000 eq. 5 or k_r of 002 eq. 6, in [0, 1] (Bando only)
  float rest_length = 0.f;     // kYangZhangExact: YangZhangSpanLength(a0, h0, kFlank), mesh units
};

// One (point, wrinkle) pair of a curve-wrinkle table.
struct CurveWrinkleEntry {
  uint32_t wrinkle = 0;  // index into the wrinkle parameters
  float distance = 0.f;  // l, distance of the point to the wrinkle's curve, mesh units, >= 0
  // Bando only: S(l; depth, width) (000 eq. 2), fixed with l on the rest pose; the builder
  // fills it (CurveProfile) so a frame multiplies by the modulation instead of calling exp().
  // Read only when `has_profile` is set.
  float profile = 0.f;
  uint32_t has_profile = 0;
};

// Curve wrinkles (docs/model.md §7-8): row i is point points[i] with its entries
// [offsets[i], offsets[i+1]) (the wrinkles whose support covers it):
//   x_i += N_i * sum_e W_e   (sum in entry order).
struct CurveWrinkleJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> normals;                 // N1 per point; every index used must exist
  span<const CurveWrinkleParams> wrinkles;    // every entry's wrinkle index must exist
  span<const uint32_t> points;                // point of each row; >= end
  span<const uint32_t> offsets;               // row -> entry CSR; >= end + 1, non-decreasing
  span<const CurveWrinkleEntry> entries;      // >= offsets[end]
  span<const float> entry_shrinkage;          // s per entry (DirectionalShrinkageJob over one
                                              // probe per entry); >= offsets[end] when any
                                              // wrinkle is kDirectional, else may be empty
  span<const float> area_ratios;              // r per point (PointAreaRatioJob); must hold every
                                              // row's point when any wrinkle is kArea
  size_t begin = 0;                           // first row
  size_t end = 0;                             // one past the last row
  span<float3> positions;                     // points, in/out (+= W N); every index used
  span<float> out_amplitudes;                 // optional: sum_e W_e per row; empty or >= end
};

// The displacement of one entry (exposed for tests): l = distance, s = shrinkage, r = area ratio.
float CurveWrinkleValue(const CurveWrinkleParams& p, float l, float s, float r);

// Sum of W_e over entries [first, last) of a row whose point has area ratio r
// (CurveWrinkleJob's per-row step): shrinkage(k) gives entry k's s, and is called only for
// directionally modulated entries (an area-modulated one never reads s).
template <class ShrinkageFn>
inline float CurveWrinkleRowSumWith(const CurveWrinkleParams* wrinkles,
                                    const CurveWrinkleEntry* entries, uint32_t first,
                                    uint32_t last, const ShrinkageFn& shrinkage, float r_point) {
  float sum = 0.f;
  for (uint32_t k = first; k < last; ++k) {
    const CurveWrinkleParams& params = wrinkles[entries[k].wrinkle];
    const bool directional = params.modulation == CurveWrinkleModulation::kDirectional;
    const float s = directional ? shrinkage(k) : 0.f;
    const float r = directional ? 1.f : r_point;
    if (entries[k].has_profile && params.profile == CurveWrinkleProfile::kBando) {
      // CurveWrinkleValue's Bando branch with S(l) precomputed: the same bits.
      sum += entries[k].profile * (directional ? DirectionalModulation(s, params.rest_amplitude)
                                               : AreaModulation(r, params.rest_amplitude));
    } else {
      sum += CurveWrinkleValue(params, entries[k].distance, s, r);
    }
  }
  return sum;
}
// The same with s read from an array indexed by entry.
inline float CurveWrinkleRowSum(const CurveWrinkleParams* wrinkles,
                                const CurveWrinkleEntry* entries, uint32_t first, uint32_t last,
                                const float* shrinkage, float r) {
  return CurveWrinkleRowSumWith(wrinkles, entries, first, last,
                                [shrinkage](uint32_t k) { return shrinkage[k]; }, r);
}

}  // namespace mimetic
