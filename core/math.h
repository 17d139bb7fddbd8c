// core/math.h: the small vector types the runtime works in (std only).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace mimetic {

inline constexpr float kPi = 3.14159265358979323846f;

struct float2 {
  float x = 0.f, y = 0.f;
};

// Three floats, tightly packed (12 bytes): position and normal streams are arrays of these.
struct float3 {
  float x = 0.f, y = 0.f, z = 0.f;
};
static_assert(sizeof(float3) == 12, "float3 must be tightly packed");

// Four floats on a 16-byte boundary: per-frame scratch that SIMD loads whole (face normals
// with a spare lane, see rig/runtime/face_kernels.h). Not a file or API stream type.
struct alignas(16) float4 {
  float x = 0.f, y = 0.f, z = 0.f, w = 0.f;
};
static_assert(sizeof(float4) == 16, "float4 must be 16 bytes");

inline float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline float3 operator-(float3 a) { return {-a.x, -a.y, -a.z}; }
inline float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float3 operator*(float s, float3 a) { return {a.x * s, a.y * s, a.z * s}; }
inline float3 operator/(float3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
inline float3& operator+=(float3& a, float3 b) { a.x += b.x; a.y += b.y; a.z += b.z; return a; }
inline float3& operator-=(float3& a, float3 b) { a.x -= b.x; a.y -= b.y; a.z -= b.z; return a; }
inline float3& operator*=(float3& a, float s) { a.x *= s; a.y *= s; a.z *= s; return a; }
inline bool operator==(float3 a, float3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
inline bool operator!=(float3 a, float3 b) { return !(a == b); }

inline float Dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float3 Cross(float3 a, float3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float Length(float3 a) { return std::sqrt(Dot(a, a)); }
inline float LengthSquared(float3 a) { return Dot(a, a); }
// Returns `fallback` for vectors too short to normalise (and for NaN input).
inline float3 NormalizeOr(float3 a, float3 fallback) {
  const float len2 = Dot(a, a);
  if (!(len2 > 1e-30f)) return fallback;
  return a * (1.f / std::sqrt(len2));
}
inline bool IsFinite(float3 a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// std::fmin / std::fmax as the compiler inlines them (GCC calls the C library for those on
// x86-64, which cost a BVH build most of its time): a NaN operand is ignored, and of two equal
// operands (+0 and -0 among them) the second is returned, as glibc's own do
// (tests/core/math_test.cpp compares them bit for bit).
inline float FMin(float a, float b) { return a < b ? a : (b == b ? b : a); }
inline float FMax(float a, float b) { return a > b ? a : (b == b ? b : a); }

// Clamp to [lo, hi]; NaN maps to `lo` (runtime inputs are clamped, never rejected).
inline float ClampOrLow(float v, float lo, float hi) {
  if (!(v >= lo)) return lo;  // also catches NaN
  return v > hi ? hi : v;
}

}  // namespace mimetic
