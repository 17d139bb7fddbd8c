// wrinkles/runtime/profiles.h: the scalar wrinkle functions of docs/model.md §6-8 (std only).
//
// Zhang, Sim, Tan 2005 (seed 001) shape, anisotropy and attenuation functions; Bando et al.
// 2002/2003 (seeds 000, 002) curve-wrinkle profile and amplitude modulations; Yang and Zhang
// 2005 (seed 004) piecewise-cubic profile and its depth update. Every function is total: any
// finite input gives a finite output (documented clamps instead of NaN), and the templates are
// instantiated for float (run time) and double (tests that need 1e-9).
#pragma once

#include <cmath>

namespace mimetic {

// ---------------------------------------------------------------------------------------------
// Zhang et al. (001), docs/model.md §6.

// Bulge height d of eq. 5 fixed by the zero-mean condition, eq. 8:
//   d = k0 (2^(alpha+1) - 1) / (2 (alpha + 1)),
// with the limit k0 ln(2) / 2 at alpha = -1 (computed through expm1 so that it is smooth there).
template <class T>
inline T ZhangBulge(T k0, T alpha) {
  const T b = alpha + T(1);
  const T ln2 = T(0.69314718055994530942);
  const T ratio = (std::fabs(b) < T(1e-8)) ? ln2 : T(std::expm1(b * ln2) / b);
  return k0 * ratio / T(2);
}

// Shape function H(w) of eq. 5 over one cycle w in [0, 2u] (`u` = half cycle, > 0):
//   t = (w - u)/u,  H = k0 (1 + t^2)^alpha t + d  (w <= u),  -k0 (1 + t^2)^alpha t + d  (w > u),
// i.e. H = d - k0 (1 + t^2)^alpha |t|: furrows (H < 0) at w = 0 and 2u, bulge d at w = u.
// w outside [0, 2u] is clamped; u <= 0 (or NaN) gives 0.
template <class T>
inline T ZhangShape(T w, T u, T k0, T alpha) {
  if (!(u > T(0))) return T(0);
  if (!(w >= T(0))) w = T(0);
  if (w > T(2) * u) w = T(2) * u;
  const T t = std::fabs((w - u) / u);
  return ZhangBulge(k0, alpha) - k0 * T(std::pow(T(1) + t * t, alpha)) * t;
}

// Anisotropic function A(eps) of eq. 11: cos(pi/2 (1 - eps)) for eps in [0, 1], 0 for eps < 0.
// eps > 1 is clamped to 1 (A = 1); NaN gives 0.
template <class T>
inline T Anisotropy(T eps) {
  if (!(eps > T(0))) return T(0);
  if (eps >= T(1)) return T(1);
  const T half_pi = T(1.57079632679489661923);
  return T(std::cos(half_pi * (T(1) - eps)));
}

// The muscle gate G(a) (docs/model.md §6, a **choice** beyond 001): the factor by which a
// muscle's own activation `a` scales its wrinkles' amplitude, smoothstep(0, gate, a) =
// x^2 (3 - 2 x) with x = clamp(a / gate, 0, 1): 0 at rest, 1 from a = gate on, with zero slope
// at both ends. `gate` <= 0 (or NaN) means no gate: G = 1, 001's amplitude by compression
// alone. NaN `a` gives 0.
template <class T>
inline T WrinkleGate(T activation, T gate) {
  if (!(gate > T(0))) return T(1);
  if (!(activation > T(0))) return T(0);
  if (activation >= gate) return T(1);
  const T x = activation / gate;
  return x * x * (T(3) - T(2) * x);
}

// Attenuation At of eq. 12 (linear muscle) and eq. 15 (sheet muscle) as a function of the
// normalised distance q = (phi_i - phi_c)/(phi - phi_c)  (or (h_i - h_c)/(Ws/2 - h_c)):
//   At = 1 for q <= 0,  At = 1 - (1 + q^2) q / 2 for 0 < q <= 1,  0 for q > 1 (outside the
// region). Continuous at q = 0 (value 1) and q = 1 (value 0). NaN gives 0.
template <class T>
inline T Attenuation(T q) {
  if (q <= T(0)) return T(1);
  if (!(q < T(1))) return T(0);
  return T(1) - (T(1) + q * q) * q / T(2);
}

// ---------------------------------------------------------------------------------------------
// Bando et al. (000 eq. 2-5, 002 eq. 4-6), docs/model.md §7.

// Curve-wrinkle shape S(l) = d (l/w - 1) exp(-l/w) (000 eq. 2), `l` >= 0 the distance from the
// furrow, `depth` d and `width` w > 0 in the units of the caller (l and w alike). S(0) = -d,
// zero at l = w, integral over [0, inf) = 0 (eq. 3). w <= 0 gives 0; negative l is mirrored.
template <class T>
inline T CurveProfile(T l, T depth, T width) {
  if (!(width > T(0))) return T(0);
  const T x = std::fabs(l) / width;
  if (!(x < T(80))) return T(0);  // exp(-80) * 80 is below any float resolution of d
  return depth * (x - T(1)) * T(std::exp(-x));
}

// Directional amplitude modulation M(s) of 000 eq. 5, `s` the shrinkage of docs/model.md §5
// (1 = fully shrunk, 0 rest, < 0 stretched), `r` in [0, 1] the relative amplitude at rest:
//   M = (1 - r) s + r  (s >= 0),   M = r exp((1/r - 1) s)  (s < 0).
// C1 at s = 0. r <= 0 gives 0 for s < 0 (the limit); s > 1 is clamped to 1; NaN s gives r.
template <class T>
inline T DirectionalModulation(T s, T r) {
  if (!(r > T(0))) r = T(0);
  if (r > T(1)) r = T(1);
  if (s != s) s = T(0);
  if (s >= T(0)) {
    if (s > T(1)) s = T(1);
    return (T(1) - r) * s + r;
  }
  if (r <= T(0)) return T(0);
  return r * T(std::exp((T(1) / r - T(1)) * s));
}

// Area amplitude modulation C(r) of 002 eq. 6, `r` the area ratio of docs/model.md §4 (1 rest,
// < 1 compressed), `kr` in [0, 1] the relative amplitude at rest:
//   C = (kr - 1) r + 1  (r <= 1),   C = kr exp((1 - 1/kr)(r - 1))  (r > 1).
// C1 at r = 1. kr <= 0 gives 0 for r > 1 (the limit); r < 0 is clamped to 0; NaN r gives kr.
template <class T>
inline T AreaModulation(T r, T kr) {
  if (!(kr > T(0))) kr = T(0);
  if (kr > T(1)) kr = T(1);
  if (r != r) r = T(1);
  if (r <= T(1)) {
    if (r < T(0)) r = T(0);
    return (kr - T(1)) * r + T(1);
  }
  if (kr <= T(0)) return T(0);
  return kr * T(std::exp((T(1) - T(1) / kr) * (r - T(1))));
}

// ---------------------------------------------------------------------------------------------
// Yang and Zhang (004), docs/model.md §8.

// Outer end A of the half profile for zero volume (004 eq. 5): A = 20 a / 3.
template <class T>
inline T YangZhangWidth(T a) {
  return T(20) * a / T(3);
}

// Half profile f(x) over x >= 0 from the furrow line, depth h, half width a > 0 (004 eq. 1-2):
//   [0, 2a]: f = 5h/(32a^3) x^3 - 29h/(32a^2) x^2 + 7h/(4a) x - h  (through (0,-h), (a,0),
//            (2a, h/8), flat at 2a),
//   [2a, A]: cubic Hermite from (2a, h/8) to (A, 0), flat at both ends, A = 20a/3,
//   x > A:   0.
// Negative x is mirrored (the profile is symmetric about the furrow). a <= 0 gives 0.
template <class T>
inline T YangZhangProfile(T x, T a, T h) {
  if (!(a > T(0))) return T(0);
  const T t = std::fabs(x) / a;  // in units of a; A = 20/3
  if (t <= T(2)) {
    return h * (((T(5) / T(32) * t - T(29) / T(32)) * t + T(7) / T(4)) * t - T(1));
  }
  const T end = T(20) / T(3);
  if (!(t < end)) return T(0);
  const T s = (t - T(2)) / (end - T(2));
  return h / T(8) * (T(1) + s * s * (T(2) * s - T(3)));
}

// Slope f'(x) of YangZhangProfile for x >= 0 (0 for a <= 0 and x > A).
template <class T>
inline T YangZhangSlope(T x, T a, T h) {
  if (!(a > T(0))) return T(0);
  const T t = std::fabs(x) / a;
  if (t <= T(2)) {
    return h / a * ((T(15) / T(32) * t - T(58) / T(32)) * t + T(7) / T(4));
  }
  const T end = T(20) / T(3);
  if (!(t < end)) return T(0);
  const T len = end - T(2);
  const T s = (t - T(2)) / len;
  return h / T(8) * T(6) * s * (s - T(1)) / (len * a);
}

// Length-preserving depth update of 004 eq. 9 for skin length ratio S = current/rest across
// the furrow (a = S a0, eq. 8): the flank [0, a] is modelled by its chord, whose length
// sqrt(h^2 + a^2) is kept:  h = sqrt(h0^2 + (1 - S^2) a0^2)  while S^2 < 1 + h0^2/a0^2, else 0.
// S < 0 is clamped to 0; NaN S gives h0.
template <class T>
inline T YangZhangDepth(T h0, T a0, T S) {
  if (S != S) return h0;
  if (S < T(0)) S = T(0);
  const T v = h0 * h0 + (T(1) - S * S) * a0 * a0;
  return v > T(0) ? T(std::sqrt(v)) : T(0);
}

// Which stretch of the half profile the exact (Newton) depth update keeps at constant length.
enum class YangZhangSpan {
  // [0, a]: the furrow flank, i.e. the exact form of the length that eq. 9 keeps through its
  // chord. docs/model.md §8 choice used by the rig (see wrinkle_jobs.h): same behaviour as eq. 9,
  // without its ~1% error.
  kFlank,
  // [0, A]: the whole half profile, eq. 6 as written in 004. With A = 20a/3 shrinking with S,
  // every bit of lost width must go into depth (h0 = 0.5 a0 becomes ~2 a0 at S = 0.8).
  kFull,
};

// Arc length of the half profile over [0, x_end] (x_end >= 0; the flat part beyond A counts
// its length): integral of sqrt(1 + f'(x)^2), composite 8-point Gauss-Legendre split at the
// profile's joints (relative accuracy better than 1e-10 for h/a up to 10). a <= 0 gives x_end.
double YangZhangArcLength(double a, double h, double x_end);

// Arc length of the span `span` of the profile (a, h): x_end = a (kFlank) or 20a/3 (kFull).
double YangZhangSpanLength(double a, double h, YangZhangSpan span);

// Exact depth update (004 eq. 6): the h >= 0 for which the span of the profile with half width
// a = S a0 has length `rest_length` (= YangZhangSpanLength(a0, h0, span), precomputed). Newton
// iteration safeguarded by bisection on [0, rest_length] (the length is convex and increasing
// in h), at most 64 iterations, never hangs; returns 0 when even h = 0 is too long (stretched
// skin), and falls back to YangZhangDepth (eq. 9) for non-finite input or non-convergence.
double YangZhangDepthNewton(double h0, double a0, double S, double rest_length,
                            YangZhangSpan span);
// Same, computing the rest length itself.
double YangZhangDepthNewton(double h0, double a0, double S, YangZhangSpan span);

}  // namespace mimetic
