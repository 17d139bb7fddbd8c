// io/gltf_bake.cpp: frames -> a .glb of morph targets and a weights animation.
//
// Written with tinygltf (already the project's glTF library, and 2.7 serialises sparse
// accessors), so the JSON and the GLB chunks are made by the same code as ExportMesh's; the
// buffer is laid out here. Based on the glTF 2.0 specification, §3.6.2.3 (sparse accessors),
// §3.7.2.2 (morph targets), §3.11 (animations).
#include "io/gltf_bake.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "core/file_util.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

// delta = frame - base per vertex (`c` components each: 3 for positions and normals, 2 for
// tension); a vertex whose components all stay within `epsilon` gets exact zeros, and
// otherwise is marked in `moved` (when given).
void FrameDeltas(const float* frame, const float* base, size_t nv, int c, float epsilon,
                 float* delta, uint8_t* moved) {
  for (size_t v = 0; v < nv; ++v) {
    float* d = delta + c * v;
    bool small = true;
    for (int i = 0; i < c; ++i) {
      d[i] = frame[c * v + i] - base[c * v + i];
      small = small && std::abs(d[i]) <= epsilon;
    }
    if (small)
      for (int i = 0; i < c; ++i) d[i] = 0.f;
    else if (moved)
      moved[v] = 1;
  }
}

// A hash of the bits of a frame's positions and (when given) normals and tension: FNV-1a's
// step over 32-bit words (one float each), only to find candidate equal frames (they are
// compared).
uint64_t FrameHash(const float* positions, const float* normals, const float* tension,
                   size_t nv) {
  uint64_t h = 1469598103934665603ull;
  auto add = [&](const float* v, size_t count) {
    for (size_t i = 0; i < count; ++i) {
      uint32_t w;
      std::memcpy(&w, v + i, sizeof w);
      h = (h ^ w) * 1099511628211ull;
    }
  };
  add(positions, nv * 3);
  if (normals) add(normals, nv * 3);
  if (tension) add(tension, nv * 2);
  return h;
}

struct Builder {
  tinygltf::Model model;
  tinygltf::Buffer buffer;

  // Appends bytes (4-byte aligned) as a new bufferView; target 0 = none.
  int View(const void* data, size_t bytes, int target) {
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = buffer.data.size();
    bv.byteLength = bytes;
    bv.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.data.insert(buffer.data.end(), p, p + bytes);
    model.bufferViews.push_back(bv);
    return int(model.bufferViews.size()) - 1;
  }
  int Accessor(int view, int component, size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.count = count;
    a.type = type;
    model.accessors.push_back(a);
    return int(model.accessors.size()) - 1;
  }
  // A float accessor of `values` (#V * c, c = 3: VEC3, c = 2: VEC2), dense or sparse
  // (whichever is fewer bytes; neither bufferView nor sparse when every value is 0). Returns
  // the accessor and, through `nonzero`, how many vertices have a non-zero value.
  int Deltas(const std::vector<float>& values, size_t nv, int c, bool with_min_max,
             bool* sparse, size_t* nonzero) {
    std::vector<uint32_t> idx;
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    bool first = true;
    for (size_t v = 0; v < nv; ++v) {
      const float* d = &values[c * v];
      bool moved = false;
      for (int i = 0; i < c; ++i) {
        moved = moved || d[i] != 0.f;
        lo[i] = first ? d[i] : std::min(lo[i], d[i]);
        hi[i] = first ? d[i] : std::max(hi[i], d[i]);
      }
      if (moved) idx.push_back(uint32_t(v));
      first = false;
    }
    *nonzero = idx.size();
    const int type = c == 2 ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_VEC3;
    const size_t index_bytes = nv < 65536 ? 2 : 4;
    const size_t dense_bytes = nv * 4 * size_t(c), sparse_bytes = idx.size() * (index_bytes + 4 * size_t(c));
    int acc;
    *sparse = false;
    if (idx.empty()) {
      acc = Accessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, nv, type);
    } else if (sparse_bytes < dense_bytes) {
      *sparse = true;
      acc = Accessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, nv, type);
      std::vector<float> packed;
      packed.reserve(idx.size() * size_t(c));
      for (uint32_t v : idx) packed.insert(packed.end(), &values[c * v], &values[c * v] + c);
      int index_view;
      if (index_bytes == 2) {
        std::vector<uint16_t> small(idx.begin(), idx.end());
        index_view = View(small.data(), small.size() * 2, 0);
      } else {
        index_view = View(idx.data(), idx.size() * 4, 0);
      }
      const int value_view = View(packed.data(), packed.size() * 4, 0);
      tinygltf::Accessor& a = model.accessors[size_t(acc)];
      a.sparse.isSparse = true;
      a.sparse.count = int(idx.size());
      a.sparse.indices.bufferView = index_view;
      a.sparse.indices.byteOffset = 0;
      a.sparse.indices.componentType = index_bytes == 2 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                        : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      a.sparse.values.bufferView = value_view;
      a.sparse.values.byteOffset = 0;
    } else {
      acc = Accessor(View(values.data(), dense_bytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_FLOAT, nv, type);
    }
    if (with_min_max) {
      model.accessors[size_t(acc)].minValues.assign(lo, lo + c);
      model.accessors[size_t(acc)].maxValues.assign(hi, hi + c);
    }
    return acc;
  }
};

bool Check(const BakedFrames& f, Diagnostics* diag) {
  const size_t nv = f.base.vertex_count(), nf = f.times.size();
  bool ok = true;
  if (nv == 0 || f.base.indices.empty() || f.base.indices.size() % 3) {
    diag->Error("", "bake: the base mesh has no vertices or no triangles");
    ok = false;
  }
  if (nf == 0) {
    diag->Error("", "bake: no frames");
    ok = false;
  }
  if (f.positions.size() != nf * nv * 3 || (!f.normals.empty() && f.normals.size() != nf * nv * 3) ||
      (!f.base.normals.empty() && f.base.normals.size() != nv) ||
      (!f.base.uvs.empty() && f.base.uvs.size() != nv) ||
      (!f.normals.empty() && f.base.normals.empty()) ||
      (!f.tension.empty() && f.tension.size() != nf * nv * 2) ||
      f.base_tension.size() != (f.tension.empty() ? 0 : nv * 2)) {
    diag->Error("", "bake: frame or attribute sizes do not match the base mesh's " +
                        std::to_string(nv) + " vertices and " + std::to_string(nf) + " frames");
    ok = false;
  }
  for (size_t k = 0; k < nf; ++k)
    if (!std::isfinite(f.times[k]) || f.times[k] < 0 || (k > 0 && !(f.times[k] > f.times[k - 1]))) {
      diag->Error("frame " + std::to_string(k), "bake: time " + std::to_string(f.times[k]) +
                                                    " is not finite, negative or not after the "
                                                    "previous frame's");
      ok = false;
      break;
    }
  if (!f.target_names.empty() && f.target_names.size() != nf) {
    diag->Error("", "bake: " + std::to_string(f.target_names.size()) + " target names for " +
                        std::to_string(nf) + " frames");
    ok = false;
  }
  for (uint32_t i : f.base.indices)
    if (i >= nv) {
      diag->Error("", "bake: index " + std::to_string(i) + " out of range");
      ok = false;
      break;
    }
  auto finite = [](const std::vector<float>& v) {
    return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
  };
  if (!finite(f.positions) || !finite(f.normals) || !finite(f.tension) ||
      !finite(f.base_tension)) {
    diag->Error("", "bake: a frame has a non-finite position, normal or tension");
    ok = false;
  }
  if (!(f.position_epsilon >= 0) || !(f.normal_epsilon >= 0) || !(f.tension_epsilon >= 0) ||
      !std::isfinite(f.position_epsilon) || !std::isfinite(f.normal_epsilon) ||
      !std::isfinite(f.tension_epsilon)) {
    diag->Error("", "bake: the epsilons must be finite numbers >= 0");
    ok = false;
  }
  if (!(f.metres_per_unit > 0) || !std::isfinite(f.metres_per_unit)) {
    diag->Error("", "bake: metres_per_unit must be a finite number > 0");
    ok = false;
  }
  return ok;
}

}  // namespace

bool BakeGlbBytes(const BakedFrames& f, std::string* out, BakeStats* stats, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  BakeStats s;
  if (!out || !Check(f, diag)) return false;
  const size_t nv = f.base.vertex_count(), nf = f.times.size();
  const bool normals = !f.base.normals.empty();
  Builder b;
  // The buffer's bound: base attributes and indices, then at most one dense position and normal
  // delta array per frame (sparse ones are smaller), the animation and alignment. Reserved once
  // (the untouched rest is never paged in) so growing it never copies what was written.
  b.buffer.data.reserve(nv * (12 + 12 + 8 + 8) + f.base.indices.size() * 4 +
                        nf * (nv * 32 + 96) + nf * (nf + 1) * 4 + 4096);
  b.model.asset.version = "2.0";
  b.model.asset.generator = "mimetic (bake)";

  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  const int pos = b.Accessor(b.View(f.base.positions.data(), nv * sizeof(float3),
                                    TINYGLTF_TARGET_ARRAY_BUFFER),
                             TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
  float3 lo = f.base.positions[0], hi = lo;
  for (const float3& p : f.base.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  b.model.accessors[size_t(pos)].minValues = {lo.x, lo.y, lo.z};
  b.model.accessors[size_t(pos)].maxValues = {hi.x, hi.y, hi.z};
  prim.attributes["POSITION"] = pos;
  if (normals)
    prim.attributes["NORMAL"] = b.Accessor(
        b.View(f.base.normals.data(), nv * sizeof(float3), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
  if (!f.base.uvs.empty())
    prim.attributes["TEXCOORD_0"] = b.Accessor(
        b.View(f.base.uvs.data(), nv * sizeof(float2), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC2);
  if (!f.tension.empty())
    prim.attributes["_TENSION"] = b.Accessor(
        b.View(f.base_tension.data(), nv * 2 * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC2);
  prim.indices = b.Accessor(b.View(f.base.indices.data(), f.base.indices.size() * 4,
                                   TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                            TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, f.base.indices.size(),
                            TINYGLTF_TYPE_SCALAR);

  // The morph targets: frame k minus the base, one per distinct frame. A frame bit-identical
  // to an earlier one (a held pose) shows that frame's target; a frame whose every delta is
  // within the epsilons shows the base (no target, all weights 0).
  std::vector<uint8_t> moved(nv, 0);
  std::vector<float> delta(nv * 3), normal_delta(normals ? nv * 3 : 0),
      tension_delta(f.tension.empty() ? 0 : nv * 2);
  std::vector<int> target_of(nf, -1);
  std::unordered_multimap<uint64_t, size_t> seen;  // frame hash -> an earlier frame
  const bool with_normal_deltas = normals && !f.normals.empty();
  const bool with_tension = !f.tension.empty();
  const bool named = !f.target_names.empty();  // a target per frame, in order
  const auto* base_positions = reinterpret_cast<const float*>(f.base.positions.data());
  const auto* base_normals = reinterpret_cast<const float*>(f.base.normals.data());
  auto same = [&](size_t a, size_t k) {
    const size_t n = nv * 3 * sizeof(float);
    return std::memcmp(&f.positions[a * nv * 3], &f.positions[k * nv * 3], n) == 0 &&
           (!with_normal_deltas ||
            std::memcmp(&f.normals[a * nv * 3], &f.normals[k * nv * 3], n) == 0) &&
           (!with_tension ||
            std::memcmp(&f.tension[a * nv * 2], &f.tension[k * nv * 2], n / 3 * 2) == 0);
  };
  auto nonzero = [](const std::vector<float>& d) {
    return std::any_of(d.begin(), d.end(), [](float x) { return x != 0.f; });
  };
  for (size_t k = 0; k < nf; ++k) {
    const float* p = &f.positions[k * nv * 3];
    const float* n = with_normal_deltas ? &f.normals[k * nv * 3] : nullptr;
    const float* t = with_tension ? &f.tension[k * nv * 2] : nullptr;
    const uint64_t h = FrameHash(p, n, t, nv);
    bool reused = false;
    for (auto [it, end] = seen.equal_range(h); it != end && !reused && !named; ++it)
      if (same(it->second, k)) {
        target_of[k] = target_of[it->second];
        reused = true;
      }
    if (reused) continue;
    seen.insert({h, k});
    FrameDeltas(p, base_positions, nv, 3, f.position_epsilon, delta.data(), moved.data());
    if (n) FrameDeltas(n, base_normals, nv, 3, f.normal_epsilon, normal_delta.data(), nullptr);
    if (t)
      FrameDeltas(t, f.base_tension.data(), nv, 2, f.tension_epsilon, tension_delta.data(),
                  nullptr);
    if (!named && !nonzero(delta) && (!n || !nonzero(normal_delta)) &&
        (!t || !nonzero(tension_delta)))
      continue;  // the base
    std::map<std::string, int> target;
    bool sparse = false, unused_sparse;
    size_t count = 0, unused_count;
    target["POSITION"] = b.Deltas(delta, nv, 3, true, &sparse, &count);
    s.sparse_targets += sparse;
    s.max_moved_in_frame = std::max(s.max_moved_in_frame, count);
    if (n) target["NORMAL"] = b.Deltas(normal_delta, nv, 3, false, &unused_sparse, &unused_count);
    if (t) target["_TENSION"] = b.Deltas(tension_delta, nv, 2, false, &unused_sparse, &unused_count);
    target_of[k] = int(prim.targets.size());
    prim.targets.push_back(std::move(target));
  }
  if (prim.targets.empty()) {
    // Every frame is the base: one all-zero target keeps the weights animation well formed.
    std::fill(delta.begin(), delta.end(), 0.f);
    std::fill(tension_delta.begin(), tension_delta.end(), 0.f);
    std::map<std::string, int> target;
    bool unused_sparse;
    size_t unused_count;
    target["POSITION"] = b.Deltas(delta, nv, 3, true, &unused_sparse, &unused_count);
    if (with_normal_deltas) target["NORMAL"] = b.Deltas(delta, nv, 3, false, &unused_sparse, &unused_count);
    if (with_tension)
      target["_TENSION"] = b.Deltas(tension_delta, nv, 2, false, &unused_sparse, &unused_count);
    prim.targets.push_back(std::move(target));
  }
  const size_t nt = prim.targets.size();
  s.moved_vertices = size_t(std::count(moved.begin(), moved.end(), 1));

  tinygltf::Mesh mesh;
  mesh.name = "baked";
  mesh.primitives.push_back(std::move(prim));
  mesh.weights.assign(nt, 0.0);
  if (named) {
    tinygltf::Value::Array names;
    for (const std::string& name : f.target_names) names.emplace_back(name);
    tinygltf::Value::Object extras;
    extras["targetNames"] = tinygltf::Value(std::move(names));
    mesh.extras = tinygltf::Value(std::move(extras));
  }
  b.model.meshes.push_back(std::move(mesh));

  tinygltf::Node node;
  node.mesh = 0;
  node.name = "mimetic_units";
  if (f.metres_per_unit != 1.0)
    node.scale = {f.metres_per_unit, f.metres_per_unit, f.metres_per_unit};
  b.model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  b.model.scenes.push_back(scene);
  b.model.defaultScene = 0;

  // The animation: input times[k]; output row k is 1 at frame k's target and 0 elsewhere
  // (all 0 for a frame that is the base); LINEAR between rows.
  std::vector<float> input(nf), output(nf * nt, 0.f);
  for (size_t k = 0; k < nf; ++k) {
    input[k] = float(f.times[k]);
    if (target_of[k] >= 0) output[k * nt + size_t(target_of[k])] = 1.f;
  }
  for (size_t k = 1; k < nf; ++k)
    if (!(input[k] > input[k - 1])) {
      diag->Error("frame " + std::to_string(k), "bake: frame times closer than a float resolves");
      return false;
    }
  const int in = b.Accessor(b.View(input.data(), nf * 4, 0), TINYGLTF_COMPONENT_TYPE_FLOAT, nf,
                            TINYGLTF_TYPE_SCALAR);
  b.model.accessors[size_t(in)].minValues = {input.front()};
  b.model.accessors[size_t(in)].maxValues = {input.back()};
  const int outp = b.Accessor(b.View(output.data(), output.size() * 4, 0),
                              TINYGLTF_COMPONENT_TYPE_FLOAT, output.size(), TINYGLTF_TYPE_SCALAR);
  tinygltf::Animation anim;
  anim.name = "clip";
  tinygltf::AnimationSampler sampler;
  sampler.input = in;
  sampler.output = outp;
  sampler.interpolation = "LINEAR";
  anim.samplers.push_back(sampler);
  tinygltf::AnimationChannel channel;
  channel.sampler = 0;
  channel.target_node = 0;
  channel.target_path = "weights";
  anim.channels.push_back(channel);
  b.model.animations.push_back(std::move(anim));
  b.model.buffers.push_back(std::move(b.buffer));

  std::ostringstream ss;
  bool ok = false;
  try {
    tinygltf::TinyGLTF writer;
    ok = writer.WriteGltfSceneToStream(&b.model, ss, false, true);
  } catch (...) {
    ok = false;
  }
  if (!ok) {
    diag->Error("", "bake: tinygltf could not serialise the animation");
    return false;
  }
  *out = ss.str();
  s.frames = nf;
  s.targets = nt;
  s.bytes = out->size();
  if (stats) *stats = s;
  return true;
}

void SetDefaultEpsilons(BakedFrames* f) {
  if (f->base.positions.empty()) return;
  float3 lo = f->base.positions[0], hi = lo;
  for (const float3& p : f->base.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  f->position_epsilon =
      1e-6f * std::sqrt((hi.x - lo.x) * (hi.x - lo.x) + (hi.y - lo.y) * (hi.y - lo.y) +
                        (hi.z - lo.z) * (hi.z - lo.z));
  f->normal_epsilon = 1e-4f;
  f->tension_epsilon = 1e-5f;
}

std::string TensionRegionsToJson(const std::vector<std::string>& names,
                                 const std::vector<double>& times,
                                 const std::vector<float>& weights) {
  nlohmann::ordered_json j;
  j["format"] = "mimetic-tension-regions";
  j["version"] = 1;
  j["times"] = times;
  nlohmann::ordered_json regions = nlohmann::ordered_json::array();
  const size_t nr = names.size();
  for (size_t i = 0; i < nr; ++i) {
    nlohmann::ordered_json curve = nlohmann::ordered_json::array();
    for (size_t k = 0; k < times.size() && k * nr + i < weights.size(); ++k)
      curve.push_back(json_reader::ShortestDecimal(weights[k * nr + i]));
    nlohmann::ordered_json region;
    region["name"] = names[i];
    region["weights"] = std::move(curve);
    regions.push_back(std::move(region));
  }
  j["regions"] = std::move(regions);
  return j.dump(2) + "\n";
}

bool WriteBakedGlb(const std::string& path, const BakedFrames& frames, BakeStats* stats,
                   Diagnostics* diag) {
  std::string bytes;
  if (!BakeGlbBytes(frames, &bytes, stats, diag)) return false;
  return WriteFileAtomic(path, bytes, diag);
}

}  // namespace mimetic
