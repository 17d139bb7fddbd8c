// rig/offline/rig_spec.h: the rig file (docs/rig-format.md) once parsed, before compiling.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "core/image.h"
#include "geometry/fingerprint.h"
#include "muscles/offline/muscle_spec.h"
#include "rig/runtime/rig.h"
#include "rig/runtime/skin_layers.h"
#include "wrinkles/offline/fine_scale.h"
#include "wrinkles/offline/wrinkle_spec.h"

namespace mimetic {

// Subcutaneous skin thickness h (docs/model.md §4), in mesh units.
struct ThicknessSpec {
  enum class Kind { kConstant, kPerVertex, kImage };
  Kind kind = Kind::kConstant;
  float value = 0.f;               // kConstant
  std::vector<float> per_vertex;   // kPerVertex: one per file vertex
  std::string image_path;          // kImage: absolute or relative to the cwd (resolved)
  GrayImage image;                 // kImage: its pixels, decoded by io (LoadRig) before BuildRig
  float min = 0.f, max = 0.f;      // kImage: black -> min, white -> max
};

// Compile-time refinement (docs/model.md §11): triangles in a wrinkle's support are split until
// their edges are shorter than `edge_fraction` times the wrinkle's width.
struct RefinementSpec {
  bool enabled = true;
  float edge_fraction = 0.25f;  // (0, 1]
  // Where a muscle's fall-off bends (docs/model.md §11): edges shorter than
  // sqrt(8 falloff_error / MuscleFalloffCurvature), so that interpolating each muscle's profile
  // linearly over an edge errs by at most falloff_error of its peak; not near the input's
  // slivers. 0 (the default for files that do not say) = off.
  float falloff_error = 0.f;  // 0 (off) or in (0, 1)
};

// A tension region (docs/tension.md): a named mask over the mesh, one weight in [0, 1] per file
// vertex; the rig keeps the points with a weight above 0.
struct TensionRegionSpec {
  std::string name;                            // unique among the regions
  float reference = kDefaultTensionReference;  // c0 > 0 (docs/model.md §19)
  std::vector<float> weights;                  // one per mesh vertex, file order, in [0, 1]
  // The rig file's sparse form (docs/rig-format.md): when `sparse`, weights[k] is vertex
  // vertices[k]'s (ascending, below the mesh's vertex count) and every other vertex has 0;
  // BuildRig makes it dense first.
  bool sparse = false;
  std::vector<uint32_t> vertices{};
};

struct NamedCurveWrinkle {
  std::string name;             // unique among curve wrinkles
  CurveWrinkleSpec spec;
};

// The jaw (docs/model.md §18, docs/rig-format.md `jaw`): a hinge through the condyles, an
// opening range and a per-point weight w in [0, 1], either explicit (one per file vertex) or
// the region function JawRegionWeight of the rest position.
struct JawSpec {
  float3 condyles[2]{};      // the subject's right, then left condyle; mesh units
  float range_deg = 0.f;     // opening at jaw = 1, degrees, (0, 90]
  // The condyles' glide at jaw = 1 (docs/model.md §18), mesh units: a carried point moves by
  // w jaw translation after its turn (forward and down on the articular eminence).
  float3 translation{};
  // The weight region (used when `weights` is empty): see JawRegionWeight.
  float3 mouth{};            // between the lips on the midline, mesh units
  float mouth_width = 0.f;   // mouth corner to corner, mesh units, > 0
  float lip_blend_deg = 2.f;     // blend half-width about the lip line between the corners
  float cheek_blend_deg = 12.f;  // blend half-width a mouth width beyond the corners
  float cheek_drop_deg = 0.f;    // the blend's centre lowered by this beyond the corners
  // Where the lips' side term fades out toward each corner, a fraction of the mouth width:
  // full at |x| <= W/2 - corner_fade W, none at the corners and beyond (docs/model.md §18).
  float corner_fade = 0.2f;
  // The lips carry no subcutaneous fat (docs/model.md §18, "the mouth's free edge"): on a mesh
  // with a slit between the lips, a point's thickness is scaled by smoothstep(0, f W, d), d its
  // distance from the slit's edge, f = thickness_fade (0 = off), W the mouth width.
  float thickness_fade = 0.3f;
  float back[2] = {0.2f, 0.6f};  // forward distance from the hinge (fractions of the
                                 // hinge-to-mouth distance) where w fades in: 0 -> 1
  float neck_deg[2] = {90.f, 180.f};  // angles below the lip line where w fades out toward the
                                      // neck: 1 above -n0, 0 below -n1 (the default fades
                                      // nothing in front of the hinge)
  std::vector<float> weights;    // explicit: one per file vertex, in [0, 1]
};

// The eyeballs the lids slide on (docs/model.md §24, docs/rig-format.md `eyes`): spheres, and
// the band of skin over them that slides: a point a muscle or the jaw moves, whose rest distance
// from the nearest eyeball's surface is d, slides with weight EyeSlideWeight(d, band).
struct EyeSphere {
  float3 center{};    // mesh units
  float radius = 0.f;  // > 0, mesh units
};
struct EyesSpec {
  std::vector<EyeSphere> spheres;  // at least one
  float band[2] = {0.f, 0.f};      // [b0, b1], 0 <= b0 < b1, mesh units from the surface
};

// The weight of a point at distance d (mesh units, negative inside) from an eyeball's surface:
// 1 for d <= b0, 0 for d >= b1, between them the smoothstep 3t^2 - 2t^3 of t = (b1 - d) /
// (b1 - b0) (C1: no crease where the band ends).
float EyeSlideWeight(float d, const float band[2]);

// The frame of the jaw's hinge: pivot = the condyles' midpoint, axis = right -> left condyle
// (unit), forward = pivot -> mouth without its axis part (unit), up = forward x axis.
struct JawFrame {
  float3 pivot, axis, forward, up;
  float reach = 0.f;  // hinge-to-mouth distance along forward, mesh units
};
// False when the condyles coincide or the mouth lies on the hinge axis.
bool MakeJawFrame(const JawSpec& jaw, JawFrame* out);

// The weight region (docs/model.md §18), at rest position p, with phi the angle of p about the
// hinge above the plane of the axis and the mouth point (degrees; phi = 0 on the lip line) and
// x the distance from the midline along the axis:
//   e    = smoothstep(0, 1, (|x| - W/2) / W)            0 between the mouth corners
//   beta = lip_blend + (cheek_blend - lip_blend) e,  phi0 = -cheek_drop e
//   w    = (1 - smoothstep(phi0 - beta, phi0 + beta, phi)) * smoothstep(b0 D, b1 D, z)
//          * smoothstep(-n1, -n0, phi)
// (W the mouth width, z the forward distance from the hinge, D = its value at the mouth, n the
// neck angles: the throat below the chin stays).
// `n`, the unit rest normal at p (or zero where unknown), decides the side on the lip line of a
// mesh whose lips are separate surfaces: between the corners phi is moved by
// -beta (1 - e) (1 - k) clamp(2 n.up, -1, 1), so a point facing up (the lower lip's top) joins
// the jaw and one facing down (the upper lip's underside) stays, however thin the slit; on a
// closed lip line the normal faces forward (n.up ~ 0) and nothing moves. k = smoothstep(W/2 -
// c W, W/2, |x|) (c = corner_fade) takes the term away toward the corners, where the slit ends
// and the skin is one surface again (a normal there is no side: the creases beside a mouth
// corner face up and down and would tear the weight).
float JawRegionWeight(const JawSpec& jaw, const JawFrame& frame, float3 p, float3 n = {});
float Smoothstep(float lo, float hi, float x);

struct RigSpec {
  std::string file;        // the rig file this came from ("" when parsed from text)
  std::string mesh_path;   // resolved against the rig file's directory
  std::string mesh_name;   // glTF mesh name; "" = first mesh
  // The mesh the per-vertex and texture-space data were made for (`mesh.fingerprint`,
  // geometry/fingerprint.h); empty in files written before it existed. BuildRig refuses a mesh
  // that does not match it when the rig has per-vertex thickness (positions and indices) or a
  // thickness image or curve wrinkles (texture coordinates too).
  MeshFingerprint mesh_fingerprint;
  std::string units;       // "mm", "cm", "dm", "m" or "in"
  ThicknessSpec thickness;
  std::vector<MuscleSpec> muscles;
  // Parallel to `muscles`: the optional wrinkle block of each muscle (docs/model.md §6). Empty
  // vector or nullopt entries mean no wrinkles. (Kept here, not in MuscleSpec, because
  // muscles/ and wrinkles/ are siblings that do not include each other.)
  std::vector<std::optional<MuscleWrinkleSpec>> muscle_wrinkles;
  std::vector<NamedCurveWrinkle> curve_wrinkles;  // docs/model.md §7-8
  SkinLayers layers;  // which skin layers to compile (all by default); docs/model.md §1 steps 3-4
  RefinementSpec refinement;
  std::optional<JawSpec> jaw;  // docs/model.md §18; absent = no jaw
  std::optional<EyesSpec> eyes;  // docs/model.md §24; absent = no eyeballs to slide on
  std::vector<TensionRegionSpec> tension_regions;  // docs/tension.md
  // Fine-scale wrinkle textures (docs/model.md §20-23, docs/rig-format.md `fine_scale`);
  // absent = none.
  std::optional<FineScaleSpec> fine_scale;
};

// The muscle geometry a wrinkle region needs (docs/model.md §6), from a muscle spec: linear R is
// Waters' Rf, phi the zone angle; sheet lines, Ls and Ws as they are. (Here because muscles/
// and wrinkles/ are siblings that do not include each other.)
WrinkleMuscleGeometry WrinkleGeometryOf(const MuscleSpec& muscle);

}  // namespace mimetic
