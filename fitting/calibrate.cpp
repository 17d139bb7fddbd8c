// fitting/calibrate.cpp: coordinate search over a template's muscle parameters (calibrate.h).
#include "fitting/calibrate.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/strings.h"
#include "fitting/anatomy.h"
#include "fitting/box_least_squares.h"
#include "fitting/compare.h"
#include "fitting/creases.h"
#include "fitting/fit.h"
#include "geometry/normal_field.h"
#include "geometry/normals.h"
#include "muscles/offline/muscle_builder.h"
#include "muscles/offline/waters.h"

namespace mimetic {
namespace {

// One training shape: its displacement from the neutral, the per-vertex weights, and the
// normal equations of the muscle basis under those weights (G = U^T W U, h = U^T W t). With a
// normal weight k, the score's metric M (per vertex w (I + k n n^T)) has its own (gm, hm, tmt).
struct Target {
  std::vector<double> t;  // 3 per vertex
  std::vector<double> w;  // 1 per vertex
  std::vector<double> tn;  // t's component along the neutral's normal, 1 per vertex
  double twt = 0.0;
  Eigen::MatrixXd g;
  Eigen::VectorXd h;
  Eigen::MatrixXd gm;  // U^T M U (empty without a normal weight)
  Eigen::VectorXd hm;  // U^T M t
  double tmt = 0.0;    // t^T M t
};

enum class Kind { kStrength, kRs, kRf, kAngle, kLength, kWidth, kInsX, kInsY, kAttX, kAttY,
                  kAttDepth, kInsDepth, kMotion, kTangentRadius };

const char* KindName(Kind k) {
  switch (k) {
    case Kind::kStrength: return "strength";
    case Kind::kRs: return "falloff_start";
    case Kind::kRf: return "falloff_end";
    case Kind::kAngle: return "zone_angle_deg";
    case Kind::kLength: return "length";
    case Kind::kWidth: return "width";
    case Kind::kInsX: return "insertion dx";
    case Kind::kInsY: return "insertion dy";
    case Kind::kAttX: return "attachment dx";
    case Kind::kAttY: return "attachment dy";
    case Kind::kAttDepth: return "attachment depth";
    case Kind::kInsDepth: return "insertion depth";
    case Kind::kMotion: return "motion";
    case Kind::kTangentRadius: return "tangent_radius";
  }
  return "?";
}

bool Multiplicative(Kind k) {
  return k == Kind::kStrength || k == Kind::kRs || k == Kind::kRf || k == Kind::kLength ||
         k == Kind::kWidth;
}

int PointCount(const TemplateMuscle& m) { return m.type == MuscleType::kSheet ? 2 : 1; }

double Get(const TemplateMuscle& m, Kind k) {
  switch (k) {
    case Kind::kStrength: return m.strength;
    case Kind::kRs: return m.falloff_start;
    case Kind::kRf: return m.falloff_end;
    case Kind::kAngle: return m.zone_angle_deg;
    case Kind::kLength: return m.length;
    case Kind::kWidth: return m.width;
    case Kind::kInsX: return m.insertion[0].offset.x;
    case Kind::kInsY: return m.insertion[0].offset.y;
    case Kind::kAttX: return m.attachment[0].offset.x;
    case Kind::kAttY: return m.attachment[0].offset.y;
    case Kind::kAttDepth: return m.attachment[0].depth;
    case Kind::kInsDepth: return m.insertion[0].depth;
    case Kind::kMotion: return m.motion == MuscleMotion::kTangent ? 1.0 : 0.0;
    case Kind::kTangentRadius: return m.tangent_radius;
  }
  return 0.0;
}

// Sets one parameter; a sheet's two points of a line move together.
void Set(TemplateMuscle* m, Kind k, double value) {
  const float v = float(value);
  const int n = PointCount(*m);
  switch (k) {
    case Kind::kStrength: m->strength = v; break;
    case Kind::kRs: m->falloff_start = v; break;
    case Kind::kRf: m->falloff_end = v; break;
    case Kind::kAngle: m->zone_angle_deg = v; break;
    case Kind::kLength: m->length = v; break;
    case Kind::kWidth: m->width = v; break;
    case Kind::kInsX: { const float d = v - m->insertion[0].offset.x; for (int i = 0; i < n; ++i) m->insertion[i].offset.x += d; break; }
    case Kind::kInsY: { const float d = v - m->insertion[0].offset.y; for (int i = 0; i < n; ++i) m->insertion[i].offset.y += d; break; }
    case Kind::kAttX: { const float d = v - m->attachment[0].offset.x; for (int i = 0; i < n; ++i) m->attachment[i].offset.x += d; break; }
    case Kind::kAttY: { const float d = v - m->attachment[0].offset.y; for (int i = 0; i < n; ++i) m->attachment[i].offset.y += d; break; }
    case Kind::kAttDepth: for (int i = 0; i < n; ++i) m->attachment[i].depth = v; break;
    case Kind::kInsDepth: for (int i = 0; i < n; ++i) m->insertion[i].depth = v; break;
    case Kind::kMotion: m->motion = value > 0.5 ? MuscleMotion::kTangent : MuscleMotion::kChord; break;
    case Kind::kTangentRadius: m->tangent_radius = v; break;
  }
}

struct Param {
  size_t muscle;  // source muscle index in the template
  Kind kind;
  double lo, hi, step, min_step;
};

// The mirror image of a source muscle (template_file's rule: landmarks mirrored, dx negated).
TemplateMuscle MirrorOf(const TemplateMuscle& src, const std::string& name) {
  TemplateMuscle c = src;
  c.name = name;
  c.mirrored_copy = true;
  for (TemplatePoint* p : {&c.attachment[0], &c.attachment[1], &c.insertion[0], &c.insertion[1]}) {
    for (int& l : p->landmarks) l = IbugMirrorLandmark(l);
    p->offset.x = -p->offset.x;
  }
  return c;
}

// A head on which every change must keep the anatomy (fitting/anatomy.h) and leave every
// triangle the right way up (docs/model.md §16): the training head and the options' others.
class ConstraintHead {
 public:
  ConstraintHead(const CalibrationHead& h, bool check_anatomy, float crease_fraction, float max_miss)
      : head_(h), check_anatomy_(check_anatomy), crease_fraction_(crease_fraction),
        max_miss_(max_miss) {}

  bool Init(const MuscleTemplate& t, Diagnostics* diag) {
    const MeshData& mesh = *head_.mesh;
    if (!ResolveLandmarks(*head_.landmarks, mesh, &lm_, diag) || !ComputeFaceFrame(lm_, &frame_, diag))
      return false;
    field_ = std::make_shared<NormalField>(span<const float3>(mesh.positions),
                                           span<const uint32_t>(mesh.indices));
    query_ = std::make_shared<const SurfaceQuery>(mesh);
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3)
      tri_normals_.push_back(TriangleNormal(mesh.positions[mesh.indices[k]],
                                            mesh.positions[mesh.indices[k + 1]],
                                            mesh.positions[mesh.indices[k + 2]], {0, 0, 0}));
    for (const MuscleRegion& r : DefaultMuscleRegions()) {
      std::vector<size_t> members;
      for (const std::string& name : r.muscles)
        for (size_t k = 0; k < t.muscles.size(); ++k)
          if (t.muscles[k].name == name) members.push_back(k);
      if (!members.empty()) regions_.push_back({r.name, members});
    }
    columns_.assign(t.muscles.size(), {});
    for (size_t i = 0; i < t.muscles.size(); ++i) {
      if (t.muscles[i].mirrored_copy) continue;
      std::vector<std::vector<float>> cols;
      const std::string why = Fit(t, i, &cols);
      if (!why.empty()) return diag->Error(head_.name + ": " + t.muscles[i].name, why), false;
      Commit(t, i, cols);
    }
    for (size_t i = 0; i < t.muscles.size(); ++i) {
      if (t.muscles[i].mirrored_copy) continue;
      const std::string why = Folds(t, i, nullptr);
      if (!why.empty()) return diag->Error(head_.name + ": " + t.muscles[i].name, why), false;
    }
    if (crease_fraction_ > 0.f) InitCreases(t);
    return true;
  }

  // Fits source muscle i of `t` (and its copy) here; "" and their columns, or why not.
  std::string Check(const MuscleTemplate& t, size_t i, std::vector<std::vector<float>>* cols) const {
    std::vector<MuscleSpec> specs;
    std::string why = Fit(t, i, cols, true, &specs);
    if (why.empty()) why = Folds(t, i, cols);
    if (why.empty()) why = Creases(t, i, specs);
    return why.empty() ? "" : head_.name + ": " + why;
  }

  void Commit(const MuscleTemplate& t, size_t i, const std::vector<std::vector<float>>& cols) {
    const std::vector<size_t> changed = Changed(t, i);
    for (size_t k = 0; k < changed.size() && k < cols.size(); ++k) columns_[changed[k]] = cols[k];
    if (meter_) MeasureCreasesOf(t, i, &own_, &waters_);
  }

  // The largest crease number over the largest with Waters' fall-offs, now and at the start.
  double crease_ratio() const { return Ratio(own_, waters_); }
  double seed_crease_ratio() const { return seed_ratio_; }

 private:
  static std::vector<size_t> Changed(const MuscleTemplate& t, size_t i) {
    std::vector<size_t> c{i};
    if (i + 1 < t.muscles.size() && t.muscles[i + 1].mirrored_copy) c.push_back(i + 1);
    return c;
  }

  std::string Fit(const MuscleTemplate& t, size_t i, std::vector<std::vector<float>>* cols,
                  bool anatomy = true, std::vector<MuscleSpec>* specs = nullptr) const {
    MuscleTemplate one;
    for (size_t k : Changed(t, i)) one.muscles.push_back(t.muscles[k]);
    RigSpec spec;
    FitReport report;
    Diagnostics diag;
    if (!FitTemplate(one, *head_.mesh, *head_.landmarks, "mm", &spec, &diag, &report, query_.get()))
      return "does not fit: " + diag.Format();
    std::string missed;
    if (const float miss = LargestMiss(report, &missed); miss > max_miss_) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "%s lies off the mesh of %s: its ray missed and the nearest "
                    "surface point is %.3g s away, more than %.3g (the fit's limit is 0.5)",
                    missed.c_str(), head_.name.c_str(), double(miss), double(max_miss_));
      return buf;
    }
    const MeshData& mesh = *head_.mesh;
    if (specs) *specs = spec.muscles;
    cols->assign(spec.muscles.size(), std::vector<float>(3 * mesh.vertex_count(), 0.f));
    for (size_t k = 0; k < spec.muscles.size(); ++k) {
      const MuscleSpec& ms = spec.muscles[k];
      const std::vector<float3>& normals = field_->At(ms.tangent_radius);
      if (check_anatomy_ && anatomy) {
        if (const MuscleAnatomy* a = FindMuscleAnatomy(ms.name)) {
          const AnatomyProbe probe = FindAnatomyProbe(*a, ms.name, mesh, lm_, report.points);
          if (probe.found) {
            const std::string why = CheckMuscleAnatomy(*a, ms, frame_, mesh.positions[probe.vertex],
                                                       normals[probe.vertex], 0.08f);
            if (!why.empty()) return why;
          }
        }
      }
      std::vector<float>& col = (*cols)[k];
      for (size_t v = 0; v < mesh.vertex_count(); ++v) {
        const float3 d = ApplyMuscleMotion(MuscleDisplacement(ms, mesh.positions[v], ms.strength),
                                           normals[v], ms.motion);
        col[3 * v] = d.x, col[3 * v + 1] = d.y, col[3 * v + 2] = d.z;
      }
    }
    return "";
  }

  // The crease rule (docs/model.md §2-3): each muscle's crease number alone at 1, with its
  // own fall-off and with Waters' (the same muscle refitted with it); the rule is on the ratio
  // of their largest values, the fidelity target's measure. A built rig measures its refined
  // surface, where a smooth field bends by little per edge and a kink stays a kink; on the
  // head's own triangles the two differ far less. So the rule measures on the head's triangles
  // split once at their edges' midpoints (the midpoints' normals the mean of their ends').
  void InitCreases(const MuscleTemplate& t) {
    const MeshData& mesh = *head_.mesh;
    const size_t n = mesh.vertex_count();
    EdgeTable edges;
    BuildEdgeTable(mesh.indices, &edges);
    fine_points_ = mesh.positions;
    mid_ends_.clear();
    for (size_t e = 0; e < edges.edge_count(); ++e) {
      const uint32_t a = EdgeKeyLow(edges.keys[e]), b = EdgeKeyHigh(edges.keys[e]);
      mid_ends_.push_back({a, b});
      fine_points_.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]));
    }
    std::vector<uint32_t> fine_tris;
    for (size_t tri = 0; 3 * tri + 2 < mesh.indices.size(); ++tri) {
      const uint32_t* c = &mesh.indices[3 * tri];
      uint32_t m[3];
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        const uint32_t e = edges.tri_edge[3 * tri + size_t(k)];
        ok &= e != EdgeTable::kNoEdge;
        m[k] = ok ? uint32_t(n + e) : 0;  // the midpoint of corner k's edge (k to k+1)
      }
      if (!ok) continue;
      const uint32_t split[12] = {c[0], m[0], m[2], m[0], c[1], m[1], m[2], m[1], c[2], m[0], m[1], m[2]};
      fine_tris.insert(fine_tris.end(), split, split + 12);
    }
    meter_ = std::make_unique<CreaseMeter>(span<const float3>(fine_points_),
                                           span<const uint32_t>(fine_tris));
    own_.assign(t.muscles.size(), 0.0);
    waters_.assign(t.muscles.size(), 0.0);
    for (size_t i = 0; i < t.muscles.size(); ++i)
      if (!t.muscles[i].mirrored_copy) MeasureCreasesOf(t, i, &own_, &waters_);
    seed_ratio_ = crease_ratio();
  }

  // The crease numbers of source muscle i of `t` (and its copy), with their own fall-offs and
  // with Waters', into (*own)[k] and (*waters)[k]; `fitted`, when given, holds those muscles
  // as already fitted here with their own fall-offs (Check's fit, not repeated).
  void MeasureCreasesOf(const MuscleTemplate& t, size_t i, std::vector<double>* own,
                        std::vector<double>* waters,
                        const std::vector<MuscleSpec>* fitted = nullptr) const {
    MuscleTemplate w = t;
    for (TemplateMuscle& m : w.muscles) m.falloff = MuscleFalloff::kWaters;
    const std::vector<size_t> changed = Changed(t, i);
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<std::vector<float>> cols;
      std::vector<MuscleSpec> specs;
      if (pass == 0 && fitted) specs = *fitted;
      else if (!Fit(pass ? w : t, i, &cols, false, &specs).empty()) continue;  // t fitted already
      for (size_t k = 0; k < changed.size() && k < specs.size(); ++k)
        (pass ? *waters : *own)[changed[k]] = Crease(specs[k]);
    }
  }

  double Crease(const MuscleSpec& ms) const {
    const std::vector<float3>& normals = field_->At(ms.tangent_radius);
    const size_t n = normals.size();
    std::vector<float3> d(fine_points_.size());
    for (size_t v = 0; v < d.size(); ++v) {
      const float3 normal =
          v < n ? normals[v]
                : NormalizeOr(normals[mid_ends_[v - n][0]] + normals[mid_ends_[v - n][1]], normals[mid_ends_[v - n][0]]);
      d[v] = ApplyMuscleMotion(MuscleDisplacement(ms, fine_points_[v], ms.strength), normal, ms.motion);
    }
    return meter_->Measure(d);
  }

  static double Ratio(const std::vector<double>& own, const std::vector<double>& waters) {
    const double w = waters.empty() ? 0.0 : *std::max_element(waters.begin(), waters.end());
    const double o = own.empty() ? 0.0 : *std::max_element(own.begin(), own.end());
    return w > 0.0 ? o / w : 0.0;
  }

  // The rule per muscle: the cap is `crease_fraction` of the largest crease number with
  // Waters' fall-offs over all muscles; after the change no muscle may be newly above the cap,
  // and none above it may crease more than before (the seed's muscles above it can only come
  // down). Within the cap for every muscle is the fidelity target itself.
  std::string Creases(const MuscleTemplate& t, size_t i, const std::vector<MuscleSpec>& fitted) const {
    if (!meter_) return "";
    std::vector<double> own = own_, waters = waters_;
    MeasureCreasesOf(t, i, &own, &waters, &fitted);
    const double cap_before = crease_fraction_ * *std::max_element(waters_.begin(), waters_.end());
    const double cap = crease_fraction_ * *std::max_element(waters.begin(), waters.end());
    for (size_t j = 0; j < own.size(); ++j) {
      if (own[j] <= cap + 1e-9) continue;
      if (own_[j] > cap_before && own[j] <= own_[j] + 1e-9) continue;
      char buf[256];
      std::snprintf(buf, sizeof buf, " creases the skin by %.2f degrees at 1, above %.2f (%.3f of "
                    "the largest with Waters' fall-offs) and above its %.2f before the change "
                    "(docs/model.md §2-3)", own[j], cap, double(crease_fraction_), own_[j]);
      return t.muscles[j].name + buf;
    }
    return "";
  }

  // Every corner of each region that holds a changed muscle, and every muscle at 1, over the
  // triangles a changed muscle moves: dot(n_posed, n_rest) must stay above 0.1.
  std::string Folds(const MuscleTemplate& t, size_t i, const std::vector<std::vector<float>>* fresh) const {
    // A region's corners keep a margin (0.1); every muscle at 1, the sum no pose of the
    // library reaches, must not turn a triangle over (0.02: a margin for the refinement of the
    // built rig, whose triangles the fold-over test checks; docs/model.md §16).
    constexpr float kMinDot = 0.1f, kMinDotAll = 0.02f;
    const MeshData& mesh = *head_.mesh;
    const std::vector<size_t> changed = Changed(t, i);
    auto column = [&](size_t k) -> const std::vector<float>& {
      if (fresh)
        for (size_t c = 0; c < changed.size() && c < fresh->size(); ++c)
          if (changed[c] == k) return (*fresh)[c];
      return columns_[k];
    };
    std::vector<uint32_t> tris;
    for (size_t tri = 0; tri < tri_normals_.size(); ++tri) {
      bool touched = false;
      for (int c = 0; c < 3 && !touched; ++c) {
        const size_t v = mesh.indices[3 * tri + size_t(c)];
        for (size_t k : changed) {
          const std::vector<float>& col = column(k);
          touched |= !col.empty() && (col[3 * v] != 0.f || col[3 * v + 1] != 0.f || col[3 * v + 2] != 0.f);
        }
      }
      if (touched) tris.push_back(uint32_t(tri));
    }
    std::vector<std::pair<std::string, std::vector<size_t>>> sets;
    for (const auto& r : regions_) {
      bool holds = false;
      for (size_t k : r.second)
        for (size_t c : changed) holds |= k == c;
      if (!holds || r.second.size() > 10) continue;
      for (uint32_t mask = 1; mask < (1u << r.second.size()); ++mask) {
        std::vector<size_t> set;
        for (size_t b = 0; b < r.second.size(); ++b)
          if (mask & (1u << b)) set.push_back(r.second[b]);
        sets.push_back({r.first, set});
      }
    }
    // And every muscle at 1 (where regions overlap, the mouth corner's six muscles).
    std::vector<size_t> all;
    for (size_t k = 0; k < t.muscles.size(); ++k) all.push_back(k);
    const size_t all_set = sets.size();
    sets.push_back({"all muscles", all});
    for (size_t si = 0; si < sets.size(); ++si) {
      const auto& [where, set] = sets[si];
      const float min_dot = si == all_set ? kMinDotAll : kMinDot;
      for (uint32_t tri : tris) {
        float3 p[3];
        for (int c = 0; c < 3; ++c) {
          const size_t v = mesh.indices[3 * size_t(tri) + size_t(c)];
          p[c] = mesh.positions[v];
          for (size_t k : set) {
            const std::vector<float>& col = column(k);
            if (!col.empty()) p[c] += float3{col[3 * v], col[3 * v + 1], col[3 * v + 2]};
          }
        }
        const float dot = Dot(TriangleNormal(p[0], p[1], p[2], {0, 0, 0}), tri_normals_[tri]);
        if (Length(tri_normals_[tri]) > 0.f && !(dot > min_dot)) {
          std::string names;
          for (size_t k : set) names += (names.empty() ? "" : "+") + t.muscles[k].name;
          char buf[160];
          std::snprintf(buf, sizeof buf, " at 1 (%s) turns triangle %u over or nearly (normal dot "
                        "%.3f <= %.2f; docs/model.md §16)", where.c_str(), tri, double(dot), double(min_dot));
          return names + buf;
        }
      }
    }
    return "";
  }

  CalibrationHead head_;
  bool check_anatomy_;
  float crease_fraction_;
  float max_miss_;  // CalibrationOptions::max_miss
  std::unique_ptr<CreaseMeter> meter_;  // on fine_points_; null without the crease rule
  std::vector<float3> fine_points_;     // the head's points, then its edges' midpoints
  std::vector<std::array<uint32_t, 2>> mid_ends_;  // each midpoint's two ends
  // Each muscle's crease number now (degrees), with its own fall-off and with Waters'.
  std::vector<double> own_, waters_;
  double seed_ratio_ = 0.0;
  // The rest normals each tangent muscle projects on (shared by copies of this head).
  std::shared_ptr<NormalField> field_;
  std::shared_ptr<const SurfaceQuery> query_;  // the head's, for its many fits
  std::vector<float3> lm_, tri_normals_;
  FaceFrame frame_;
  std::vector<std::pair<std::string, std::vector<size_t>>> regions_;
  std::vector<std::vector<float>> columns_;
};

class Calibrator {
 public:
  Calibrator(const MeshData& head, const Landmarks& landmarks, const CalibrationOptions& options)
      : head_(head), landmarks_(landmarks), options_(options) {}

  bool Init(const MuscleTemplate& tmpl, const std::vector<CalibrationShape>& shapes,
            Diagnostics* diag) {
    if (shapes.empty()) return diag->Error("shapes", "no training shape; expected at least one"), false;
    if (!ResolveLandmarks(landmarks_, head_, &lm_, diag) || !ComputeFaceFrame(lm_, &frame_, diag))
      return false;
    field_ = std::make_shared<NormalField>(span<const float3>(head_.positions),
                                           span<const uint32_t>(head_.indices));
    normals_ = field_->At(0.f);
    query_ = std::make_shared<const SurfaceQuery>(head_);
    const size_t n = head_.vertex_count();
    for (const CalibrationShape& s : shapes) {
      if (!s.mesh || !SameTopology(head_, *s.mesh))
        return diag->Error(s.name, "has another topology than the neutral head (expected the "
                                   "same vertices and triangles)"), false;
      Target t;
      t.t.resize(3 * n);
      t.w.resize(n);
      double largest = 0.0;
      for (size_t v = 0; v < n; ++v) {
        const float3 d = s.mesh->positions[v] - head_.positions[v];
        t.t[3 * v] = d.x, t.t[3 * v + 1] = d.y, t.t[3 * v + 2] = d.z;
        largest = std::max(largest, double(Length(d)));
      }
      if (!(largest > 0.0)) return diag->Error(s.name, "does not move: every vertex is where the "
                                                       "neutral has it"), false;
      for (size_t v = 0; v < n; ++v) {
        const double len = std::sqrt(t.t[3 * v] * t.t[3 * v] + t.t[3 * v + 1] * t.t[3 * v + 1] +
                                     t.t[3 * v + 2] * t.t[3 * v + 2]);
        t.w[v] = len > options_.region_fraction * largest ? 1.0 : options_.outside_weight;
        t.twt += t.w[v] * len * len;
        const double tn = NormalPart(&t.t[3 * v], v);
        t.tn.push_back(tn);
        t.tmt += t.w[v] * (len * len + options_.normal_weight * tn * tn);
      }
      targets_.push_back(std::move(t));
    }
    tmpl_ = tmpl;
    const size_t m = tmpl_.muscles.size();
    columns_.assign(m, std::vector<double>(3 * n, 0.0));
    normal_parts_.assign(m, std::vector<double>(options_.normal_weight > 0.f ? n : 0, 0.0));
    for (Target& t : targets_) {
      t.g = Eigen::MatrixXd::Zero(m, m), t.h = Eigen::VectorXd::Zero(m);
      if (options_.normal_weight > 0.f)
        t.gm = Eigen::MatrixXd::Zero(m, m), t.hm = Eigen::VectorXd::Zero(m);
    }
    for (size_t i = 0; i < m; ++i) {
      if (tmpl_.muscles[i].mirrored_copy) continue;
      std::vector<std::vector<double>> cols;
      std::string why;
      if (!Columns(i, tmpl_, &cols, &why, diag)) return false;
      Store(i, cols);
    }
    heads_.emplace_back(CalibrationHead{"the training head", &head_, &landmarks_}, false,
                        options_.crease_fraction, options_.max_miss);
    for (const CalibrationHead& h : options_.check_heads)
      heads_.emplace_back(h, h.anatomy, options_.crease_fraction, options_.max_miss);
    for (ConstraintHead& h : heads_)
      if (!h.Init(tmpl_, diag)) return false;
    return true;
  }

  // Mean score and per-shape scores of the current template.
  double Objective(std::vector<double>* scores) const {
    double sum = 0.0;
    if (scores) scores->clear();
    for (const Target& t : targets_) {
      const double s = Score(t);
      sum += s;
      if (scores) scores->push_back(s);
    }
    return sum / double(targets_.size());
  }

  // Tries `candidate` for source muscle i; returns the objective (or +inf when refused) and
  // leaves the state unchanged.
  double Try(size_t i, const TemplateMuscle& candidate, bool* anatomy_refused) {
    *anatomy_refused = false;
    MuscleTemplate t = tmpl_;
    t.muscles[i] = candidate;
    SyncCopy(&t, i);
    std::vector<std::vector<double>> cols;
    std::string why;
    Diagnostics quiet;
    if (!Columns(i, t, &cols, &why, &quiet)) {
      *anatomy_refused = !why.empty();
      return INFINITY;
    }
    for (const ConstraintHead& h : heads_) {
      std::vector<std::vector<float>> head_cols;
      if (!h.Check(t, i, &head_cols).empty()) {
        *anatomy_refused = true;
        return INFINITY;
      }
    }
    const auto saved_g = Snapshot();
    const auto saved_cols = Pair(i);
    Store(i, cols);
    const double obj = Objective(nullptr);
    Restore(saved_g, i, saved_cols);
    return obj;
  }

  void Accept(size_t i, const TemplateMuscle& candidate) {
    tmpl_.muscles[i] = candidate;
    SyncCopy(&tmpl_, i);
    std::vector<std::vector<double>> cols;
    std::string why;
    Diagnostics quiet;
    Columns(i, tmpl_, &cols, &why, &quiet);
    Store(i, cols);
    for (ConstraintHead& h : heads_) {
      std::vector<std::vector<float>> head_cols;
      h.Check(tmpl_, i, &head_cols);
      h.Commit(tmpl_, i, head_cols);
    }
  }

  const MuscleTemplate& current() const { return tmpl_; }
  // Per head: the crease ratio of the seed and of the current template (empty without the rule).
  void CreaseRatios(std::vector<double>* seed, std::vector<double>* now) const {
    seed->clear(), now->clear();
    if (options_.crease_fraction <= 0.f) return;
    for (const ConstraintHead& h : heads_)
      seed->push_back(h.seed_crease_ratio()), now->push_back(h.crease_ratio());
  }

 private:
  // Index of the mirrored copy of source muscle i, or npos.
  size_t CopyOf(const MuscleTemplate& t, size_t i) const {
    return i + 1 < t.muscles.size() && t.muscles[i + 1].mirrored_copy ? i + 1 : size_t(-1);
  }
  void SyncCopy(MuscleTemplate* t, size_t i) const {
    const size_t c = CopyOf(*t, i);
    if (c != size_t(-1)) t->muscles[c] = MirrorOf(t->muscles[i], t->muscles[c].name);
  }

  // Fits source muscle i (and its copy) of `t` and computes their basis columns; refuses a
  // muscle that the fit refuses or that breaks the anatomy (why = the reason).
  bool Columns(size_t i, const MuscleTemplate& t, std::vector<std::vector<double>>* cols,
               std::string* why, Diagnostics* diag) const {
    MuscleTemplate one;
    one.muscles.push_back(t.muscles[i]);
    const size_t c = CopyOf(t, i);
    if (c != size_t(-1)) one.muscles.push_back(t.muscles[c]);
    for (const TemplateMuscle& m : one.muscles) {
      // On the written digits: an attachment 0.00001 deeper than its insertion prints level.
      const double att = TemplateDigits(m.attachment[0].depth);
      const double ins = TemplateDigits(m.insertion[0].depth);
      char broken[160] = "";
      if (att < options_.min_attachment_depth)
        std::snprintf(broken, sizeof broken, "attachment depth %g is shallower than %g s", att,
                      double(options_.min_attachment_depth));
      else if (att <= ins)
        std::snprintf(broken, sizeof broken, "attachment depth %g is not deeper than the "
                      "insertion's %g (at the 4 digits a template file holds)", att, ins);
      else if (ins > options_.max_insertion_depth)
        std::snprintf(broken, sizeof broken, "insertion depth %g is deeper than %g s", ins,
                      double(options_.max_insertion_depth));
      else if (m.type == MuscleType::kLinear ? !(m.falloff_start < m.falloff_end)
                                             : !(m.falloff_start < m.length))
        std::snprintf(broken, sizeof broken, "falloff_start %g is not below %s %g",
                      double(m.falloff_start), m.type == MuscleType::kLinear ? "falloff_end" : "length",
                      double(m.type == MuscleType::kLinear ? m.falloff_end : m.length));
      if (broken[0]) return diag->Error(m.name, std::string("outside the constraints: ") + broken), false;
    }
    RigSpec spec;
    FitReport report;
    if (!FitTemplate(one, head_, landmarks_, "mm", &spec, diag, &report, query_.get())) return false;
    const size_t n = head_.vertex_count();
    cols->assign(spec.muscles.size(), std::vector<double>(3 * n, 0.0));
    for (size_t k = 0; k < spec.muscles.size(); ++k) {
      const MuscleSpec& ms = spec.muscles[k];
      const std::vector<float3>& normals = field_->At(ms.tangent_radius);
      if (const MuscleAnatomy* a = FindMuscleAnatomy(ms.name)) {
        const AnatomyProbe probe = FindAnatomyProbe(*a, ms.name, head_, lm_, report.points);
        if (probe.found) {
          // 8% of the strength, above the fit tests' 5%: the skin layers move the probe too.
          *why = CheckMuscleAnatomy(*a, ms, frame_, head_.positions[probe.vertex],
                                    normals[probe.vertex], 0.08f);
          if (!why->empty()) return diag->Error(ms.name, *why), false;
        }
      }
      std::vector<double>& col = (*cols)[k];
      for (size_t v = 0; v < n; ++v) {
        const float3 d = ApplyMuscleMotion(MuscleDisplacement(ms, head_.positions[v], ms.strength),
                                           normals[v], ms.motion);
        col[3 * v] = d.x, col[3 * v + 1] = d.y, col[3 * v + 2] = d.z;
      }
    }
    return true;
  }

  std::vector<std::vector<double>> Pair(size_t i) const {
    std::vector<std::vector<double>> p{columns_[i]};
    const size_t c = CopyOf(tmpl_, i);
    if (c != size_t(-1)) p.push_back(columns_[c]);
    return p;
  }
  struct Equations {
    Eigen::MatrixXd g, gm;
    Eigen::VectorXd h, hm;
  };
  std::vector<Equations> Snapshot() const {
    std::vector<Equations> s;
    for (const Target& t : targets_) s.push_back({t.g, t.gm, t.h, t.hm});
    return s;
  }
  void Restore(const std::vector<Equations>& s, size_t i, const std::vector<std::vector<double>>& cols) {
    for (size_t k = 0; k < targets_.size(); ++k) {
      Target& t = targets_[k];
      t.g = s[k].g, t.gm = s[k].gm, t.h = s[k].h, t.hm = s[k].hm;
    }
    SetColumn(i, cols[0]);
    const size_t c = CopyOf(tmpl_, i);
    if (c != size_t(-1) && cols.size() > 1) SetColumn(c, cols[1]);
  }

  // columns_[k] = col, and its normal components (one per vertex) for the normal weight.
  void SetColumn(size_t k, const std::vector<double>& col) {
    columns_[k] = col;
    if (options_.normal_weight > 0.f) {
      const size_t n = head_.vertex_count();
      std::vector<double>& np = normal_parts_[k];
      np.resize(n);
      for (size_t v = 0; v < n; ++v) np[v] = NormalPart(&col[3 * v], v);
    }
  }

  // Replaces the columns of source muscle i (and its copy) and their rows of every G and h.
  void Store(size_t i, const std::vector<std::vector<double>>& cols) {
    std::vector<size_t> changed{i};
    const size_t c = CopyOf(tmpl_, i);
    if (c != size_t(-1)) changed.push_back(c);
    for (size_t k = 0; k < changed.size() && k < cols.size(); ++k) SetColumn(changed[k], cols[k]);
    const size_t n = head_.vertex_count(), m = columns_.size();
    for (Target& t : targets_) {
      for (size_t a : changed) {
        const std::vector<double>& ca = columns_[a];
        const std::vector<double>& na = normal_parts_[a];
        for (size_t b = 0; b < m; ++b) {
          const std::vector<double>& cb = columns_[b];
          double sum = 0.0;
          for (size_t v = 0; v < n; ++v)
            sum += t.w[v] * (ca[3 * v] * cb[3 * v] + ca[3 * v + 1] * cb[3 * v + 1] +
                             ca[3 * v + 2] * cb[3 * v + 2]);
          t.g(a, b) = t.g(b, a) = sum;
          if (t.gm.size() == 0) continue;
          const std::vector<double>& nb = normal_parts_[b];
          double extra = 0.0;  // + k sum w (ca . n)(cb . n)
          for (size_t v = 0; v < n; ++v) extra += t.w[v] * na[v] * nb[v];
          t.gm(a, b) = t.gm(b, a) = sum + options_.normal_weight * extra;
        }
        double sum = 0.0;
        for (size_t v = 0; v < n; ++v)
          sum += t.w[v] * (ca[3 * v] * t.t[3 * v] + ca[3 * v + 1] * t.t[3 * v + 1] +
                           ca[3 * v + 2] * t.t[3 * v + 2]);
        t.h(a) = sum;
        if (t.hm.size() == 0) continue;
        double extra = 0.0;
        for (size_t v = 0; v < n; ++v) extra += t.w[v] * na[v] * t.tn[v];
        t.hm(a) = sum + options_.normal_weight * extra;
      }
    }
  }

  // The component of a displacement (3 doubles) along the neutral's normal at vertex v.
  double NormalPart(const double* d, size_t v) const {
    const float3 n = normals_[v];
    return d[0] * n.x + d[1] * n.y + d[2] * n.z;
  }

  // min over a in [0,1]^m of (U a - t)^T W (U a - t) / t^T W t, on the reduced system:
  // G = L L^T, so |W^1/2 (U a - t)|^2 = |L^T a - L^-1 h|^2 + t^T W t - |L^-1 h|^2.
  double Score(const Target& t) const {
    const Eigen::Index m = t.g.rows();
    Eigen::MatrixXd g = t.g;
    const double eps = 1e-10 * std::max(1e-30, g.diagonal().maxCoeff());
    g.diagonal().array() += eps;
    const Eigen::LLT<Eigen::MatrixXd> llt(g);
    const Eigen::MatrixXd r = llt.matrixU();  // L^T, upper
    const Eigen::VectorXd c = llt.matrixL().solve(t.h);
    const size_t cols = size_t(m);
    std::vector<double> a(cols * cols), b(cols), lo(cols, 0.0), hi(cols, 1.0);
    for (Eigen::Index row = 0; row < m; ++row) {
      b[size_t(row)] = c(row);
      for (Eigen::Index col = 0; col < m; ++col) a[size_t(row * m + col)] = r(row, col);
    }
    BoxLeastSquaresProblem p;
    p.a = a.data(), p.b = b.data(), p.rows = size_t(m), p.cols = size_t(m);
    p.lo = lo.data(), p.hi = hi.data();
    BoxLeastSquaresResult res;
    if (!SolveBoxLeastSquares(p, &res)) return 1.0;
    if (t.gm.size() == 0) {
      const double residual = t.twt - c.squaredNorm() + res.residual2;
      return std::max(0.0, residual) / t.twt;
    }
    // The same activations, measured in the score's metric: (U a - t)^T M (U a - t).
    const Eigen::Map<const Eigen::VectorXd> x(res.x.data(), m);
    const double residual = x.dot(t.gm * x) - 2.0 * x.dot(t.hm) + t.tmt;
    return std::max(0.0, residual) / t.tmt;
  }

  const MeshData& head_;
  const Landmarks& landmarks_;
  const CalibrationOptions& options_;
  std::shared_ptr<NormalField> field_;  // the rest normals tangent muscles project on
  std::shared_ptr<const SurfaceQuery> query_;  // the head's, for its many fits
  std::vector<float3> lm_, normals_;    // normals_: the neutral's own (the score's metric)
  std::vector<ConstraintHead> heads_;
  FaceFrame frame_;
  std::vector<Target> targets_;
  MuscleTemplate tmpl_;
  std::vector<std::vector<double>> columns_;
  std::vector<std::vector<double>> normal_parts_;  // NormalPart of each column, per vertex
};

std::vector<Param> ParamsFor(const MuscleTemplate& seed, size_t i, const CalibrationOptions& o) {
  const TemplateMuscle& m = seed.muscles[i];
  std::vector<Param> p;
  const double lg = std::log(1.25), ls = std::log(1.4);
  auto mult = [&](Kind k, double lo_f, double hi_f, double step) {
    const double v = Get(m, k);
    p.push_back({i, k, std::log(v * lo_f), std::log(v * hi_f), step, step / 8});
  };
  auto add = [&](Kind k, double lo, double hi, double step) {
    p.push_back({i, k, lo, hi, step, step / 8});
  };
  mult(Kind::kStrength, 0.33, 6.0, ls);
  if (m.type == MuscleType::kLinear) {
    mult(Kind::kRs, 0.5, 2.5, lg);
    mult(Kind::kRf, 0.5, 2.5, lg);
    add(Kind::kAngle, 10.0, 80.0, 6.0);
  } else {
    mult(Kind::kLength, 0.6, 1.8, lg);
    mult(Kind::kWidth, 0.6, 1.8, lg);
    mult(Kind::kRs, 0.5, 1.8, lg);
  }
  const double r = o.offset_reach;
  for (Kind k : {Kind::kInsX, Kind::kInsY, Kind::kAttX, Kind::kAttY})
    add(k, Get(m, k) - r, Get(m, k) + r, 0.04);
  add(Kind::kAttDepth, o.min_attachment_depth, 0.25, 0.02);
  add(Kind::kInsDepth, 0.005, o.max_insertion_depth, 0.008);
  // A motion the seed names is kept: an anatomical decision (the frontalis slides the brow
  // skin over the bone, docs/model.md §17) that the muscles-alone residual cannot make, since
  // it measures vertex positions and not the surface they make (docs/calibration.md).
  if (o.calibrate_motion && !m.motion_given) add(Kind::kMotion, 0.0, 1.0, 1.0);
  // The ball a tangent muscle's normals are averaged over (geometry/normal_field.h), when the
  // seed names the motion: 0 (each point's own normal) to 1 s.
  if (m.motion_given && m.motion == MuscleMotion::kTangent) add(Kind::kTangentRadius, 0.0, 1.0, 0.1);
  return p;
}

double Value(const TemplateMuscle& m, const Param& p) {
  return Multiplicative(p.kind) ? std::log(Get(m, p.kind)) : Get(m, p.kind);
}
// At the digits the template file holds (TemplateDigits), so the constraints and the objective
// are those of the template that `mimetic calibrate` writes.
void SetValue(TemplateMuscle* m, const Param& p, double x) {
  Set(m, p.kind, TemplateDigits(Multiplicative(p.kind) ? std::exp(x) : x));
}

}  // namespace

bool ScoreTemplate(const MuscleTemplate& tmpl, const MeshData& head, const Landmarks& landmarks,
                   const std::vector<CalibrationShape>& shapes, const CalibrationOptions& options,
                   std::vector<double>* scores, Diagnostics* diag) {
  Calibrator c(head, landmarks, options);
  if (!c.Init(tmpl, shapes, diag)) return false;
  c.Objective(scores);
  return true;
}

bool CalibrateTemplate(const MuscleTemplate& seed, const MeshData& head,
                       const Landmarks& landmarks, const std::vector<CalibrationShape>& shapes,
                       const CalibrationOptions& options, MuscleTemplate* out,
                       CalibrationReport* report, Diagnostics* diag) {
  CalibrationReport rep;
  for (const CalibrationShape& s : shapes) rep.shapes.push_back(s.name);
  std::vector<size_t> sources;
  for (size_t i = 0; i < seed.muscles.size(); ++i) {
    if (seed.muscles[i].mirrored_copy) continue;
    if (!options.muscles.empty() &&
        std::find(options.muscles.begin(), options.muscles.end(), seed.muscles[i].name) ==
            options.muscles.end())
      continue;
    sources.push_back(i);
  }
  for (const std::string& name : options.muscles) {
    bool found = false;
    for (size_t i : sources) found |= seed.muscles[i].name == name;
    if (!found) {
      diag->Error("muscles", "no source muscle named \"" + name + "\" in the template (a "
                             "mirrored copy changes with its source)");
      return false;
    }
  }
  Calibrator c(head, landmarks, options);
  if (!c.Init(seed, shapes, diag)) return false;
  rep.objective_before = c.Objective(&rep.score_before);
  std::vector<double> unused;
  c.CreaseRatios(&rep.crease_ratio_before, &unused);
  char line[512];
  auto head_name = [&](size_t h) {
    return h ? options.check_heads[h - 1].name : std::string("the training head");
  };
  if (options.progress && !rep.crease_ratio_before.empty()) {
    std::string ratios;
    for (size_t h = 0; h < rep.crease_ratio_before.size(); ++h) {
      std::snprintf(line, sizeof line, "%s%.3f on %s", h ? ", " : "", rep.crease_ratio_before[h],
                    head_name(h).c_str());
      ratios += line;
    }
    std::snprintf(line, sizeof line, "crease rule: each muscle at most %.3f of the largest "
                  "crease number with Waters' fall-offs, or, above it, not growing; the seed's "
                  "largest over Waters' largest: ", double(options.crease_fraction));
    options.progress(line + ratios);
  }
  double best = rep.objective_before;
  std::vector<Param> params;
  for (size_t i : sources)
    for (const Param& p : ParamsFor(seed, i, options)) params.push_back(p);
  for (int pass = 0; pass < options.passes; ++pass) {
    int accepted = 0;
    for (Param& p : params) {
      if (p.step < p.min_step) continue;
      const TemplateMuscle& now = c.current().muscles[p.muscle];
      const double x = Value(now, p);
      double best_x = x, best_obj = best;
      for (double dir : {+1.0, -1.0}) {
        double nx = p.kind == Kind::kMotion ? 1.0 - x : x + dir * p.step;
        if (p.kind == Kind::kMotion && dir < 0) break;
        nx = std::clamp(nx, p.lo, p.hi);
        if (nx == x) continue;
        TemplateMuscle cand = now;
        SetValue(&cand, p, nx);
        bool refused = false;
        const double obj = c.Try(p.muscle, cand, &refused);
        ++rep.evaluations;
        rep.refused_anatomy += refused;
        if (obj < best_obj - 1e-7) best_obj = obj, best_x = nx;
      }
      if (best_x != x) {
        TemplateMuscle cand = c.current().muscles[p.muscle];
        SetValue(&cand, p, best_x);
        c.Accept(p.muscle, cand);
        ++accepted;
        ++rep.accepted;
        if (options.progress) {
          const double shown = Multiplicative(p.kind) ? std::exp(best_x) : best_x;
          std::snprintf(line, sizeof line, "  %s %s -> %.4g: objective %.4f -> %.4f",
                        cand.name.c_str(), KindName(p.kind), shown, best, best_obj);
          options.progress(line);
        }
        best = best_obj;
      } else if (p.kind != Kind::kMotion) {
        p.step *= 0.5;
      } else {
        p.step = 0.0;  // tried both motions once
      }
    }
    if (options.progress) {
      std::snprintf(line, sizeof line, "pass %d: objective %.4f (%d changes, %d evaluations)",
                    pass + 1, best, accepted, rep.evaluations);
      options.progress(line);
    }
    if (accepted == 0) break;
  }
  rep.objective_after = c.Objective(&rep.score_after);
  c.CreaseRatios(&unused, &rep.crease_ratio_after);
  // A wrinkle region starts at lambda_w R from the attachment (docs/model.md §6; R = Rf or Ls):
  // keep that distance as the seed has it (the frontalis regions line up across the forehead),
  // whatever R the search chose. The wrinkles do not enter the muscles-alone score.
  MuscleTemplate result = c.current();
  for (size_t i = 0; i < result.muscles.size(); ++i) {
    TemplateMuscle& m = result.muscles[i];
    const TemplateMuscle& s = seed.muscles[i];
    if (!m.wrinkles || !s.wrinkles) continue;
    const bool linear = m.type == MuscleType::kLinear;
    const double r_seed = linear ? s.falloff_end : s.length, r_now = linear ? m.falloff_end : m.length;
    if (r_now > 0.0)
      m.wrinkles->lambda_w = float(std::clamp(s.wrinkles->lambda_w * r_seed / r_now, 0.0, 0.95));
  }
  if (out) *out = result;
  if (report) *report = rep;
  return true;
}

}  // namespace mimetic
