// fitting/solve.cpp: SolveActivations (fitting/solve.h).
#include "fitting/solve.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/strings.h"
#include "fitting/box_least_squares.h"
#include "fitting/compare.h"
#include "geometry/normals.h"
#include "rig/runtime/evaluate_job.h"

namespace mimetic {
namespace {

// The rig's output positions of its first `count` vertices at `activations`.
class Evaluator {
 public:
  Evaluator(const Rig& rig, uint32_t count)
      : rig_(rig), context_(rig), count_(count), buffer_(3 * size_t(rig.vertex_count())) {}
  void Run(const std::vector<float>& activations, bool layers, std::vector<float3>* out) {
    EvaluateJob job;
    job.rig = &rig_;
    job.context = &context_;
    job.activations = activations;
    job.out_positions = buffer_;
    job.layers.thickness = job.layers.muscle_wrinkles = job.layers.curve_wrinkles = layers;
    job.Run();  // validated by the caller: activations sized, buffer sized, context for rig
    out->resize(count_);
    for (uint32_t v = 0; v < count_; ++v)
      (*out)[v] = {buffer_[3 * v], buffer_[3 * v + 1], buffer_[3 * v + 2]};
  }

 private:
  const Rig& rig_;
  EvaluateContext context_;
  uint32_t count_;
  std::vector<float> buffer_;
};

// The error seen by the objective: e + (s - 1) n (n . e), so that |M e|^2 = |e - n (n . e)|^2 +
// s^2 (n . e)^2 (SolveOptions::height_weight = s^2). Identity when s = 1.
float3 Weigh(const std::vector<float3>& normals, float s, uint32_t v, float3 e) {
  if (s == 1.f) return e;
  return e + normals[v] * ((s - 1.f) * Dot(normals[v], e));
}

double Residual(const std::vector<float3>& posed, const MeshData& target,
                const std::vector<float>& weight, const std::vector<float3>& normals, float s) {
  double sum = 0.0;
  for (size_t v = 0; v < posed.size(); ++v) {
    if (weight[v] <= 0.f) continue;
    const float3 d = Weigh(normals, s, uint32_t(v), posed[v] - target.positions[v]);
    sum += double(weight[v]) * (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
  }
  return sum;
}

}  // namespace

bool SolveActivations(const Rig& rig, const MeshData& neutral, const MeshData& target,
                      const SolveOptions& options, SolveResult* out, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics* d = diag ? diag : &local;
  *out = SolveResult{};
  const size_t errors = d->ErrorCount();
  if (!SameTopology(neutral, target))
    d->Error("target", "has " + std::to_string(target.vertex_count()) + " vertices and " +
                           std::to_string(target.triangle_count()) + " triangles; expected the "
                           "rig mesh's topology (" + std::to_string(neutral.vertex_count()) +
                           " vertices, " + std::to_string(neutral.triangle_count()) +
                           " triangles, the same triangles)");
  if (!(options.outside_weight >= 0.f && options.outside_weight <= 1.f))
    d->Error("outside weight", "expected a number in [0, 1]");
  if (options.refine_steps < 0 || options.refine_steps > 100)
    d->Error("refine steps", "expected a whole number in [0, 100]");
  if (!(options.ridge >= 0.0) || !std::isfinite(options.ridge))
    d->Error("ridge", "expected a finite number >= 0");
  if (!(options.height_weight >= 1e-6 && options.height_weight <= 1e6))
    d->Error("height weight", "expected a number in [1e-6, 1e6]");
  if (!std::isfinite(options.region_threshold))
    d->Error("region threshold", "expected a finite number (mesh units; < 0 for the default)");
  const uint32_t nv = uint32_t(neutral.vertex_count()), nm = rig.muscle_count();
  if (rig.vertex_count() < nv)
    d->Error("rig", "has " + std::to_string(rig.vertex_count()) + " output vertices, fewer than "
                    "its mesh's " + std::to_string(nv));
  if (d->ErrorCount() != errors) return false;

  // The unknowns: the selected muscles, L/R pairs joined under `mirror`.
  std::vector<uint8_t> selected(nm, options.muscles.empty() ? 1 : 0);
  for (uint32_t m : options.muscles) {
    if (m >= nm) {
      d->Error("muscles", "index " + std::to_string(m) + " is out of range; the rig has " +
                              std::to_string(nm) + " muscles");
      return false;
    }
    selected[m] = 1;
  }
  std::vector<std::vector<uint32_t>> unknowns;
  std::vector<uint8_t> taken(nm, 0);
  for (uint32_t m = 0; m < nm; ++m) {
    if (!selected[m] || taken[m]) continue;
    std::vector<uint32_t> group = {m};
    taken[m] = 1;
    const std::string& name = rig.muscle_names()[m];
    if (options.mirror && (EndsWith(name, "_L") || EndsWith(name, "_R"))) {
      const std::string other = name.substr(0, name.size() - 1) + (EndsWith(name, "_L") ? "R" : "L");
      const int o = rig.FindMuscle(other);
      if (o >= 0 && !selected[uint32_t(o)]) {
        d->Error("muscles", "'" + name + "' is selected and its mirror '" + other +
                                "' is not; --mirror solves both sides as one value");
        return false;
      }
      if (o >= 0 && !taken[uint32_t(o)]) {
        group.push_back(uint32_t(o));
        taken[uint32_t(o)] = 1;
      }
    }
    unknowns.push_back(group);
  }
  if (unknowns.empty()) {
    d->Error("muscles", "nothing to solve for (the rig has no muscles)");
    return false;
  }
  const size_t nu = unknowns.size();
  out->unknowns = uint32_t(nu);

  // The rest shape must be the neutral: the first #V output vertices are the input vertices.
  Evaluator eval(rig, nv);
  std::vector<float> activations(nm, 0.f);
  std::vector<float3> rest, layered, posed;
  eval.Run(activations, false, &rest);
  double far = 0.0;
  for (uint32_t v = 0; v < nv; ++v) far = std::max(far, double(Length(rest[v] - neutral.positions[v])));
  if (far > 1e-4 * (1.0 + double(Length(neutral.positions[0])))) {
    d->Error("rig", "its rest output does not start with its mesh's vertices (a vertex is " +
                        std::to_string(far) + " away); expected the rig built from this mesh");
    return false;
  }

  // Region and weights.
  double largest = 0.0;
  for (uint32_t v = 0; v < nv; ++v)
    largest = std::max(largest, double(Length(target.positions[v] - rest[v])));
  if (largest <= 0.0) {
    d->Error("target", "does not move from the rig's rest shape; nothing to solve");
    return false;
  }
  out->region_threshold = options.region_threshold >= 0.f ? options.region_threshold
                                                          : float(0.02 * largest);
  std::vector<float> weight(nv, options.outside_weight);
  for (uint32_t v = 0; v < nv; ++v)
    if (Length(target.positions[v] - rest[v]) > out->region_threshold) {
      weight[v] = 1.f;
      ++out->region_count;
    }
  if (out->region_count == 0) {
    d->Error("region", "no target vertex moves more than " + std::to_string(out->region_threshold) +
                           " from the rest shape");
    return false;
  }
  std::vector<uint32_t> rows;  // vertices with a row block
  for (uint32_t v = 0; v < nv; ++v)
    if (weight[v] > 0.f) rows.push_back(v);

  // The height weight: the error's component along the neutral's normals counts s^2 times.
  // The normals serve it and the height-first optimum of `reach`.
  const float height_scale = float(std::sqrt(options.height_weight));
  const std::vector<float3> height_normals =
      options.height_weight != 1.0 || options.reach ? ComputeVertexNormals(neutral)
                                                    : std::vector<float3>{};

  // Solves the bounded problem min |sqrt(w) (J delta - r)|^2, lo <= delta <= hi, with the
  // columns of J given per unknown as displacements of the target's vertices.
  auto bounded_step = [&](const std::vector<std::vector<float3>>& columns,
                          const std::vector<float3>& residual, const std::vector<double>& lo,
                          const std::vector<double>& hi, std::vector<double>* delta) {
    const size_t nr = 3 * rows.size();
    std::vector<double> a(nr * nu), b(nr);
    double scale = 0.0;
    for (size_t k = 0; k < nu; ++k) {
      double norm2 = 0.0;
      for (size_t i = 0; i < rows.size(); ++i) {
        const double s = std::sqrt(double(weight[rows[i]]));
        const float3 c = Weigh(height_normals, height_scale, rows[i], columns[k][rows[i]]);
        a[(3 * i) * nu + k] = s * c.x;
        a[(3 * i + 1) * nu + k] = s * c.y;
        a[(3 * i + 2) * nu + k] = s * c.z;
        norm2 += s * s * (double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z);
      }
      scale = std::max(scale, norm2);
    }
    for (size_t i = 0; i < rows.size(); ++i) {
      const double s = std::sqrt(double(weight[rows[i]]));
      const float3 r = Weigh(height_normals, height_scale, rows[i], residual[rows[i]]);
      b[3 * i] = s * r.x;
      b[3 * i + 1] = s * r.y;
      b[3 * i + 2] = s * r.z;
    }
    BoxLeastSquaresResult result;
    const BoxLeastSquaresProblem problem{.a = a.data(), .b = b.data(), .rows = nr, .cols = nu,
                                         .lo = lo.data(), .hi = hi.data(),
                                         .ridge = options.ridge * scale};
    if (!SolveBoxLeastSquares(problem, &result)) return false;
    *delta = result.x;
    return true;
  };
  auto set_activations = [&](const std::vector<double>& x) {
    for (size_t k = 0; k < nu; ++k)
      for (uint32_t m : unknowns[k]) activations[m] = float(std::clamp(x[k], 0.0, 1.0));
  };

  // 1. The linear solve on the muscle basis (skin layers off: exactly linear).
  std::vector<std::vector<float3>> columns(nu);
  for (size_t k = 0; k < nu; ++k) {
    std::fill(activations.begin(), activations.end(), 0.f);
    for (uint32_t m : unknowns[k]) activations[m] = 1.f;
    eval.Run(activations, false, &posed);
    columns[k].resize(nv);
    for (uint32_t v = 0; v < nv; ++v) columns[k][v] = posed[v] - rest[v];
  }
  std::vector<float3> residual(nv);
  for (uint32_t v = 0; v < nv; ++v) residual[v] = target.positions[v] - rest[v];
  std::vector<double> x(nu, 0.0), lo(nu, 0.0), hi(nu, 1.0);
  if (!bounded_step(columns, residual, lo, hi, &x)) {
    d->Error("solve", "the least-squares problem is not finite (a muscle or the target has "
                      "non-finite values)");
    return false;
  }
  // The same linear problem without bounds (SolveOptions::reach): what any activations of
  // these muscles could make. Its residual, and the bounded one, are taken on the basis.
  auto basis_residual = [&](const std::vector<double>& a, std::vector<float3>* made) {
    double sum = 0.0;
    if (made) made->assign(rest.begin(), rest.end());
    for (uint32_t v : rows) {
      double m[3] = {rest[v].x, rest[v].y, rest[v].z};
      for (size_t k = 0; k < nu; ++k) {
        m[0] += a[k] * columns[k][v].x;
        m[1] += a[k] * columns[k][v].y;
        m[2] += a[k] * columns[k][v].z;
      }
      if (made) (*made)[v] = {float(m[0]), float(m[1]), float(m[2])};
      const double dx = m[0] - target.positions[v].x, dy = m[1] - target.positions[v].y,
                   dz = m[2] - target.positions[v].z;
      sum += double(weight[v]) * (dx * dx + dy * dy + dz * dz);
    }
    return sum;
  };
  if (options.reach) {
    // Bounds far outside any activation a rig would use stand for none (the solver wants
    // finite ones; the ridge keeps dependent muscles determined).
    std::vector<double> free_lo(nu, -1e6), free_hi(nu, 1e6), free_x;
    if (!bounded_step(columns, residual, free_lo, free_hi, &free_x)) {
      d->Error("solve", "the unbounded least-squares problem is not finite");
      return false;
    }
    out->has_reach = true;
    SolveReach& reach = out->reach;
    reach.activations.assign(nm, 0.f);
    for (size_t k = 0; k < nu; ++k)
      for (uint32_t m : unknowns[k]) reach.activations[m] = float(free_x[k]);
    reach.motion = basis_residual(std::vector<double>(nu, 0.0), nullptr);
    reach.residual = basis_residual(free_x, &reach.posed);
    reach.bounded_residual = basis_residual(x, nullptr);
    // The height alone: columns and motion projected on the neutral's normals, n (n . u).
    const std::vector<float3>& normals = height_normals;
    auto along = [&](uint32_t v, float3 u) { return normals[v] * Dot(normals[v], u); };
    std::vector<std::vector<float3>> height_columns(nu, std::vector<float3>(nv));
    std::vector<float3> height_target(nv);
    for (uint32_t v : rows) {
      for (size_t k = 0; k < nu; ++k) height_columns[k][v] = along(v, columns[k][v]);
      height_target[v] = along(v, residual[v]);
    }
    std::vector<double> height_x;
    if (!bounded_step(height_columns, height_target, free_lo, free_hi, &height_x)) {
      d->Error("solve", "the unbounded least-squares problem of the height is not finite");
      return false;
    }
    reach.height_activations.assign(nm, 0.f);
    for (size_t k = 0; k < nu; ++k)
      for (uint32_t m : unknowns[k]) reach.height_activations[m] = float(height_x[k]);
    basis_residual(height_x, &reach.height_posed);
    for (uint32_t v : rows) {
      const double t = Dot(normals[v], target.positions[v] - rest[v]);
      const double e = Dot(normals[v], reach.height_posed[v] - target.positions[v]);
      reach.height_motion += double(weight[v]) * t * t;
      reach.height_residual += double(weight[v]) * e * e;
    }
  }

  const bool layers = options.skin_layers;
  std::fill(activations.begin(), activations.end(), 0.f);
  eval.Run(activations, layers, &layered);
  out->neutral_residual = Residual(layered, target, weight, height_normals, height_scale);
  set_activations(x);
  eval.Run(activations, layers, &layered);
  double current = out->linear_residual = Residual(layered, target, weight, height_normals, height_scale);

  // 2. Gauss-Newton steps with every layer on.
  const double h = 1e-3;
  for (int step = 0; layers && step < options.refine_steps; ++step) {
    for (size_t k = 0; k < nu; ++k) {
      std::vector<double> xp = x;
      const double dk = x[k] + h <= 1.0 ? h : -h;
      xp[k] += dk;
      set_activations(xp);
      eval.Run(activations, layers, &posed);
      columns[k].resize(nv);
      for (uint32_t v = 0; v < nv; ++v) columns[k][v] = (posed[v] - layered[v]) * float(1.0 / dk);
    }
    for (uint32_t v = 0; v < nv; ++v) residual[v] = target.positions[v] - layered[v];
    for (size_t k = 0; k < nu; ++k) {
      lo[k] = -x[k];
      hi[k] = 1.0 - x[k];
    }
    std::vector<double> delta;
    if (!bounded_step(columns, residual, lo, hi, &delta)) break;
    bool improved = false;
    for (double s = 1.0; s >= 1.0 / 16.0 && !improved; s *= 0.5) {
      std::vector<double> xt = x;
      for (size_t k = 0; k < nu; ++k) xt[k] = std::clamp(x[k] + s * delta[k], 0.0, 1.0);
      set_activations(xt);
      eval.Run(activations, layers, &posed);
      const double r = Residual(posed, target, weight, height_normals, height_scale);
      if (r < current) {
        x = xt;
        current = r;
        layered = posed;
        improved = true;
      }
    }
    if (!improved) break;
    ++out->refine_steps_taken;
  }
  set_activations(x);
  out->activations = activations;
  out->residual = current;
  out->posed = layered;
  return true;
}

}  // namespace mimetic
