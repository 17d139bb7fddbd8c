// expressions/offline/clip_builder.cpp: resolving a clip against a rig (docs/expressions.md).
// The tangent limiter is the monotonicity box of F. N. Fritsch and R. E. Carlson, "Monotone
// piecewise cubic interpolation", SIAM J. Numer. Anal. 17(2):238-246, 1980; the "clamped"
// tangent is the weighted harmonic mean of F. N. Fritsch and J. Butland, "A method for
// constructing local monotone piecewise cubic interpolants", SIAM J. Sci. Stat. Comput.
// 5(2):300-304, 1984 (MATLAB's pchip).
#include "expressions/offline/clip_builder.h"

#include "expressions/offline/activation_binding.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

namespace mimetic {
namespace {

std::string Channel(size_t i) { return "channels[" + std::to_string(i) + "]"; }

double Sign(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

}  // namespace

std::vector<float> ClipTangents(const std::vector<ClipKeySpec>& keys) {
  const size_t n = keys.size();
  std::vector<float> out(n, 0.f);
  if (n < 2) return out;
  std::vector<double> h(n - 1), d(n - 1);
  for (size_t j = 0; j + 1 < n; ++j) {
    h[j] = double(keys[j + 1].t) - double(keys[j].t);
    d[j] = (double(keys[j + 1].v) - double(keys[j].v)) / h[j];
  }
  for (size_t k = 0; k < n; ++k) {
    const bool first = k == 0, last = k + 1 == n;
    double m = 0.0;
    if (keys[k].tangent == KeyTangent::kAuto) {
      if (first) m = d[0];
      else if (last) m = d[n - 2];
      else m = (double(keys[k + 1].v) - double(keys[k - 1].v)) /
               (double(keys[k + 1].t) - double(keys[k - 1].t));
    } else if (!first && !last && d[k - 1] * d[k] > 0.0) {
      const double w1 = 2.0 * h[k] + h[k - 1], w2 = h[k] + 2.0 * h[k - 1];
      m = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k]);
    }
    // The limiter: the secants beside key k.
    const double s = first ? d[0] : d[k - 1];
    const double t = last ? d[n - 2] : d[k];
    if (s == 0.0 || t == 0.0 || Sign(s) != Sign(t) || Sign(m) != Sign(s)) {
      m = 0.0;
    } else {
      const double bound = 3.0 * std::min(std::fabs(s), std::fabs(t));
      m = Sign(m) * std::min(std::fabs(m), bound);
    }
    out[k] = float(m);
  }
  return out;
}

bool ClipBuilder::Build(const ClipSpec& clip, const std::vector<std::string>& muscle_names,
                        const std::vector<ClipExpression>& expressions, CompiledClip* out,
                        Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  if (!CheckClipSpec(clip, diag)) return false;
  if (muscle_names.size() > std::numeric_limits<uint32_t>::max() / 2) {
    diag->Error("", "the rig has too many muscles for a clip");
    return false;
  }
  const uint32_t muscle_count = uint32_t(muscle_names.size());
  std::map<std::string, uint32_t> muscle_index;
  for (uint32_t m = 0; m < muscle_count; ++m) muscle_index.insert({muscle_names[m], m});
  std::vector<std::string> expression_names;
  for (const ClipExpression& e : expressions) expression_names.push_back(e.name);

  struct Resolved {
    size_t spec;       // channels[spec]
    ClipChannelKind kind;
    ClipLayer layer;
    uint32_t target;   // muscle, or index into `used`
  };
  std::vector<Resolved> resolved;
  std::vector<size_t> used;                  // expressions[used[row]] is compiled row `row`
  std::map<size_t, uint32_t> row_of;         // expressions index -> row
  std::vector<long> driven_by(muscle_count, -1);  // muscle -> the channel spec driving it
  long jaw_driven_by = -1;
  // "jaw" names the rig's jaw opening, unless the rig has a muscle of that name.
  const bool jaw_is_muscle = muscle_index.count(kJawInputName) > 0;
  size_t key_count = 0;

  for (size_t i = 0; i < clip.channels.size(); ++i) {
    const ClipChannelSpec& c = clip.channels[i];
    key_count += c.keys.size();
    if (c.kind == ClipChannelKind::kMuscle && c.target == kJawInputName && !jaw_is_muscle) {
      jaw_driven_by = long(i);  // once: CheckClipSpec refuses a target named twice
      resolved.push_back({i, ClipChannelKind::kJaw, ClipLayer::kOverride, 0});
      continue;
    }
    if (c.kind == ClipChannelKind::kMuscle) {
      std::vector<uint32_t> targets;
      if (const auto it = muscle_index.find(c.target); it != muscle_index.end()) {
        targets.push_back(it->second);
      } else {
        const auto l = muscle_index.find(c.target + "_L"), r = muscle_index.find(c.target + "_R");
        if (l != muscle_index.end() && r != muscle_index.end()) targets = {l->second, r->second};
      }
      if (targets.empty()) {
        diag->Error(Channel(i) + ".muscle",
                    "unknown muscle \"" + c.target + "\"" +
                        (muscle_names.empty() ? std::string(" (the rig has no muscles)")
                                              : "; closest: " + ClosestNames(muscle_names, c.target)));
        continue;
      }
      for (uint32_t m : targets) {
        if (driven_by[m] >= 0) {
          diag->Error(Channel(i) + ".muscle",
                      "\"" + c.target + "\" drives " + muscle_names[m] + ", already driven by " +
                          Channel(size_t(driven_by[m])) + "; expected each muscle in at most "
                          "one channel");
          continue;
        }
        driven_by[m] = long(i);
        resolved.push_back({i, ClipChannelKind::kMuscle, ClipLayer::kOverride, m});
      }
      continue;
    }
    // An expression channel.
    std::vector<size_t> matches;
    for (size_t e = 0; e < expressions.size(); ++e)
      if (expressions[e].name == c.target) matches.push_back(e);
    const std::string at = Channel(i) + ".expression";
    if (matches.empty()) {
      diag->Error(at, "unknown expression \"" + c.target + "\"" +
                          (expressions.empty()
                               ? std::string(" (no expressions were given)")
                               : "; closest: " + ClosestNames(expression_names, c.target)));
      continue;
    }
    if (matches.size() > 1) {
      std::string list;
      for (size_t j = 0; j < matches.size(); ++j)
        list += (j ? ", " : "") + std::to_string(matches[j]);
      diag->Error(at, "expression \"" + c.target + "\" is given " +
                          std::to_string(matches.size()) + " times (expressions " + list +
                          "); expected each name once");
      continue;
    }
    const size_t e = matches[0];
    bool good = true;
    std::map<std::string, size_t> seen;
    for (size_t j = 0; j < expressions[e].activations.size(); ++j) {
      const auto& [muscle, value] = expressions[e].activations[j];
      const std::string what = "expression \"" + c.target + "\": muscle \"" + muscle + "\"";
      const bool jaw = muscle == kJawInputName && !jaw_is_muscle;
      if (!jaw && !muscle_index.count(muscle)) {
        diag->Error(at, what + " is not in the rig" +
                            (muscle_names.empty() ? std::string(" (the rig has no muscles)")
                                                  : "; closest: " + ClosestNames(muscle_names, muscle)));
        good = false;
      } else if (!seen.insert({muscle, j}).second) {
        diag->Error(at, what + " is given twice; expected each muscle once");
        good = false;
      }
      if (!(value >= 0.f && value <= 1.f)) {
        diag->Error(at, what + " has activation " + std::to_string(value) +
                            "; expected an activation in [0, 1]");
        good = false;
      }
    }
    if (!good) continue;
    auto [it, inserted] = row_of.insert({e, uint32_t(used.size())});
    if (inserted) used.push_back(e);
    resolved.push_back({i, ClipChannelKind::kExpression, c.layer, it->second});
  }
  if (key_count * 2 > std::numeric_limits<uint32_t>::max())
    diag->Error("channels", "has " + std::to_string(key_count) + " keys; expected fewer than " +
                                std::to_string(std::numeric_limits<uint32_t>::max() / 2));
  if (diag->ErrorCount() != before) return false;

  CompiledClip c;
  c.name_ = clip.name;
  c.duration_ = ClipDuration(clip);
  c.end_ = clip.end;
  c.muscle_count_ = muscle_count;
  c.expression_count_ = uint32_t(used.size());
  c.key_offsets_.push_back(0);
  for (const Resolved& r : resolved) {
    const ClipChannelSpec& spec = clip.channels[r.spec];
    c.kinds_.push_back(r.kind);
    c.layers_.push_back(r.layer);
    c.targets_.push_back(r.target);
    const std::vector<float> tangents = ClipTangents(spec.keys);
    for (size_t k = 0; k < spec.keys.size(); ++k) {
      c.key_times_.push_back(spec.keys[k].t);
      c.key_values_.push_back(spec.keys[k].v);
      c.key_tangents_.push_back(tangents[k]);
      c.key_interps_.push_back(spec.keys[k].interp);
    }
    c.key_offsets_.push_back(uint32_t(c.key_times_.size()));
  }
  c.expression_activations_.assign(size_t(muscle_count) * used.size(), 0.f);
  c.expression_masks_.assign(size_t(muscle_count) * used.size(), 0);
  c.expression_jaws_.assign(used.size(), 0.f);
  c.expression_jaw_masks_.assign(used.size(), 0);
  c.animates_jaw_ = jaw_driven_by >= 0;
  for (size_t row = 0; row < used.size(); ++row) {
    for (const auto& [muscle, value] : expressions[used[row]].activations) {
      if (muscle == kJawInputName && !jaw_is_muscle) {
        c.expression_jaws_[row] = value;
        c.expression_jaw_masks_[row] = 1;
        c.animates_jaw_ = true;
        continue;
      }
      const size_t at = row * muscle_count + muscle_index.at(muscle);
      c.expression_activations_[at] = value;
      c.expression_masks_[at] = 1;
    }
  }
  c.built_ = true;
  *out = std::move(c);
  return true;
}

}  // namespace mimetic
