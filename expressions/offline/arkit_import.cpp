// expressions/offline/arkit_import.cpp: a take through an ARKit map into a clip
// (expressions/offline/arkit_import.h, docs/arkit.md "Importing a take").
#include "expressions/offline/arkit_import.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>

#include "expressions/runtime/clip.h"

namespace mimetic {

int FindArkitShape(const std::vector<ArkitShapeActivations>& shapes, const std::string& name) {
  if (name.empty()) return -1;
  std::string other = name;
  const unsigned char c = static_cast<unsigned char>(other[0]);
  other[0] = char(std::islower(c) ? std::toupper(c) : std::tolower(c));
  for (size_t i = 0; i < shapes.size(); ++i)
    if (shapes[i].name == name || shapes[i].name == other) return int(i);
  return -1;
}

std::vector<float> ArkitFrameActivations(const std::vector<ArkitShapeActivations>& shapes,
                                         const std::vector<int>& channel_shape,
                                         const std::vector<std::string>& muscle_names,
                                         const float* weights) {
  std::unordered_map<std::string, size_t> index;
  for (size_t m = 0; m < muscle_names.size(); ++m) index.emplace(muscle_names[m], m);
  std::vector<double> sum(muscle_names.size(), 0.0);
  for (size_t c = 0; c < channel_shape.size(); ++c) {
    if (channel_shape[c] < 0) continue;
    const ArkitShapeActivations& s = shapes[size_t(channel_shape[c])];
    if (s.none) continue;
    for (const auto& [muscle, a] : s.activations)
      if (const auto it = index.find(muscle); it != index.end())
        sum[it->second] += double(weights[c]) * double(a);
  }
  std::vector<float> out(sum.size());
  for (size_t m = 0; m < sum.size(); ++m) out[m] = float(std::clamp(sum[m], 0.0, 1.0));
  return out;
}

void ReduceLinearKeys(std::vector<ClipKeySpec>* keys, float tolerance) {
  if (keys->size() < 3) return;
  const std::vector<ClipKeySpec>& in = *keys;
  std::vector<ClipKeySpec> out = {in.front()};
  size_t kept = 0;  // index in `in` of the last key kept
  for (size_t i = 1; i + 1 < in.size(); ++i) {
    // May key i go? The line from in[kept] to in[i + 1] must reproduce every key in (kept, i].
    const ClipKeySpec& a = in[kept];
    const ClipKeySpec& b = in[i + 1];
    bool fits = true;
    for (size_t j = kept + 1; j <= i && fits; ++j) {
      const double s = (double(in[j].t) - a.t) / (double(b.t) - a.t);
      const double v = double(a.v) + s * (double(b.v) - a.v);
      fits = std::fabs(v - double(in[j].v)) <= double(tolerance);
    }
    if (!fits) {
      out.push_back(in[i]);
      kept = i;
    }
  }
  out.push_back(in.back());
  *keys = std::move(out);
}

bool ImportArkitTake(const ArkitTake& take, const std::vector<ArkitShapeActivations>& shapes,
                     const std::vector<std::string>& muscle_names, const std::string& clip_name,
                     ArkitImport* out, Diagnostics* diag) {
  const size_t nc = take.names.size(), nf = take.times.size();
  if (nf == 0) {
    diag->Error("take", "has no frames; expected at least one");
    return false;
  }
  if (take.weights.size() != nf * nc) {
    diag->Error("take", "internal error: weights do not match frames x channels");
    return false;
  }
  bool ok = true;
  for (const ArkitShapeActivations& s : shapes)
    for (const auto& [muscle, a] : s.activations)
      if (std::find(muscle_names.begin(), muscle_names.end(), muscle) == muscle_names.end() &&
          muscle != kJawInputName) {  // "jaw" on a rig without one: unmapped below
        diag->Error("map: " + s.name, "muscle \"" + muscle + "\" is not one of the rig's");
        ok = false;
      }
  if (!ok) return false;

  ArkitImport result;
  std::vector<int> channel_shape(nc);
  for (size_t c = 0; c < nc; ++c) {
    channel_shape[c] = FindArkitShape(shapes, take.names[c]);
    const bool none = channel_shape[c] >= 0 && shapes[size_t(channel_shape[c])].none;
    // A shape that drives nothing this rig has (only the jaw, on a rig without one).
    bool no_jaw = false;
    if (channel_shape[c] >= 0 && !none) {
      const ArkitShapeActivations& s = shapes[size_t(channel_shape[c])];
      no_jaw = !s.activations.empty() &&
               std::all_of(s.activations.begin(), s.activations.end(), [&](const auto& a) {
                 return std::find(muscle_names.begin(), muscle_names.end(), a.first) ==
                        muscle_names.end();
               });
    }
    if (channel_shape[c] < 0 || none || no_jaw) {
      ArkitUnmapped u{take.names[c], none, no_jaw, 0};
      for (size_t f = 0; f < nf; ++f) u.nonzero += take.weights[f * nc + c] != 0.f;
      result.unmapped.push_back(u);
    }
  }
  // Per muscle, a linear key per frame.
  std::vector<std::vector<ClipKeySpec>> keys(muscle_names.size());
  std::vector<bool> moves(muscle_names.size(), false);
  for (size_t f = 0; f < nf; ++f) {
    const std::vector<float> a =
        ArkitFrameActivations(shapes, channel_shape, muscle_names, &take.weights[f * nc]);
    for (size_t m = 0; m < a.size(); ++m) {
      keys[m].push_back({take.times[f], a[m], KeyInterp::kLinear, KeyTangent::kAuto});
      moves[m] = moves[m] || a[m] != 0.f;
    }
  }
  result.clip.name = clip_name;
  result.clip.duration = take.times.back() > 0.f ? take.times.back() : -1.f;
  result.clip.end = ClipEnd::kClamp;
  for (size_t m = 0; m < muscle_names.size(); ++m) {
    if (!moves[m]) continue;
    ClipChannelSpec ch;
    ch.kind = ClipChannelKind::kMuscle;
    ch.target = muscle_names[m];
    ch.keys = std::move(keys[m]);
    ReduceLinearKeys(&ch.keys);
    result.clip.channels.push_back(std::move(ch));
  }
  if (result.clip.channels.empty()) {
    diag->Error("take", "moves no muscle: every mapped weight is 0 (or no channel maps)");
    *out = std::move(result);
    return false;
  }
  *out = std::move(result);
  return true;
}

std::string ArkitUnmappedWarning(const std::vector<ArkitUnmapped>& unmapped) {
  if (unmapped.empty()) return "";
  std::string unknown, none, no_jaw;
  for (const ArkitUnmapped& u : unmapped) {
    std::string& list = u.no_jaw ? no_jaw : (u.none ? none : unknown);
    if (!list.empty()) list += ", ";
    list += u.name + " (" + std::to_string(u.nonzero) + " non-zero frame" +
            (u.nonzero == 1 ? "" : "s") + ")";
  }
  std::string text = std::to_string(unmapped.size()) + " channel" +
                     (unmapped.size() == 1 ? " is" : "s are") + " not used: ";
  if (!unknown.empty()) text += unknown + " (not ARKit blendshape names)";
  if (!none.empty())
    text += (unknown.empty() ? "" : "; ") + none +
            " (the map marks them \"none\": the rig's muscles cannot make them)";
  if (!no_jaw.empty())
    text += (unknown.empty() && none.empty() ? "" : "; ") + no_jaw +
            " (the map drives the jaw with them, and the rig has no jaw)";
  return text;
}

}  // namespace mimetic
