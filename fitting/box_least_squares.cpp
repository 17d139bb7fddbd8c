// fitting/box_least_squares.cpp: bounded-variable least squares (Stark and Parker 1995) on
// the normal equations.
#include "fitting/box_least_squares.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mimetic {
namespace {

enum class Bound { kFree, kLow, kHigh };

bool AllFinite(const double* v, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

std::string CheckProblem(const BoxLeastSquaresProblem& p) {
  if (p.cols == 0) return "no unknowns (cols = 0)";
  if (!p.lo || !p.hi) return "missing bounds";
  if (p.rows > 0 && (!p.a || !p.b)) return "missing A or b";
  if (!AllFinite(p.a, p.rows * p.cols)) return "A has a non-finite entry";
  if (!AllFinite(p.b, p.rows)) return "b has a non-finite entry";
  if (!AllFinite(p.lo, p.cols) || !AllFinite(p.hi, p.cols)) return "a bound is not finite";
  for (size_t i = 0; i < p.cols; ++i)
    if (p.lo[i] > p.hi[i])
      return "lower bound above upper bound for unknown " + std::to_string(i);
  if (!(p.ridge >= 0.0) || !std::isfinite(p.ridge)) return "ridge must be finite and >= 0";
  return "";
}

}  // namespace

bool SolveBoxLeastSquares(const BoxLeastSquaresProblem& p, BoxLeastSquaresResult* out) {
  *out = BoxLeastSquaresResult{};
  out->error = CheckProblem(p);
  if (!out->error.empty()) return false;
  const Eigen::Index n = Eigen::Index(p.cols);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> a(p.a, Eigen::Index(p.rows), n);
  const Eigen::Map<const Eigen::VectorXd> b(p.b, Eigen::Index(p.rows));
  const Eigen::Map<const Eigen::VectorXd> lo(p.lo, n), hi(p.hi, n);
  // f(x) = x^T G x / 2 - c^T x has the minimiser of |A x - b|^2 + ridge |x|^2.
  Eigen::MatrixXd g = a.transpose() * a;
  g.diagonal().array() += p.ridge;
  const Eigen::VectorXd c = a.transpose() * b;
  // Scale of the gradient, for the KKT test: |G|_inf |x|_inf + |c|_inf.
  const double range = std::max(1.0, std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));
  const double tol = 1e-10 * (g.cwiseAbs().rowwise().sum().maxCoeff() * range +
                              c.cwiseAbs().maxCoeff()) + 1e-300;

  // Start at the feasible point nearest 0; a variable strictly inside its bounds is free.
  Eigen::VectorXd x(n);
  std::vector<Bound> state(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    x[i] = std::clamp(0.0, lo[i], hi[i]);
    state[size_t(i)] = x[i] == lo[i] ? Bound::kLow : (x[i] == hi[i] ? Bound::kHigh : Bound::kFree);
  }

  // Minimises f over the free variables with the bound ones held, stepping back to the first
  // bound crossed and binding it until the unconstrained minimiser of the free set is feasible.
  auto optimise_free_set = [&]() {
    for (Eigen::Index pass = 0; pass <= n; ++pass) {
      std::vector<Eigen::Index> free;
      for (Eigen::Index i = 0; i < n; ++i)
        if (state[size_t(i)] == Bound::kFree) free.push_back(i);
      if (free.empty()) return;
      const Eigen::Index k = Eigen::Index(free.size());
      Eigen::MatrixXd gff(k, k);
      Eigen::VectorXd rhs(k);
      for (Eigen::Index r = 0; r < k; ++r) {
        double s = c[free[size_t(r)]];
        for (Eigen::Index j = 0; j < n; ++j)
          if (state[size_t(j)] != Bound::kFree) s -= g(free[size_t(r)], j) * x[j];
        rhs[r] = s;
        for (Eigen::Index q = 0; q < k; ++q) gff(r, q) = g(free[size_t(r)], free[size_t(q)]);
      }
      // A whisker of regularisation keeps LDLT defined when free columns are dependent.
      gff.diagonal().array() += 1e-14 * (gff.diagonal().cwiseAbs().maxCoeff() + 1e-300);
      const Eigen::VectorXd z = gff.ldlt().solve(rhs);
      double alpha = 1.0;
      for (Eigen::Index r = 0; r < k; ++r) {
        const Eigen::Index i = free[size_t(r)];
        if (!std::isfinite(z[r])) { alpha = 0.0; break; }
        if (z[r] < lo[i]) alpha = std::min(alpha, (lo[i] - x[i]) / (z[r] - x[i]));
        if (z[r] > hi[i]) alpha = std::min(alpha, (hi[i] - x[i]) / (z[r] - x[i]));
      }
      alpha = std::clamp(alpha, 0.0, 1.0);
      bool bound_any = false;
      for (Eigen::Index r = 0; r < k; ++r) {
        const Eigen::Index i = free[size_t(r)];
        const double step = std::isfinite(z[r]) ? z[r] - x[i] : 0.0;
        x[i] = alpha >= 1.0 ? z[r] : x[i] + alpha * step;
        // Bind what reached (or, by rounding, crossed) a bound on this step.
        if (alpha < 1.0 && (x[i] <= lo[i] || z[r] < lo[i]) && x[i] - lo[i] <= 1e-12 * range) {
          x[i] = lo[i];
          state[size_t(i)] = Bound::kLow;
          bound_any = true;
        } else if (alpha < 1.0 && (x[i] >= hi[i] || z[r] > hi[i]) && hi[i] - x[i] <= 1e-12 * range) {
          x[i] = hi[i];
          state[size_t(i)] = Bound::kHigh;
          bound_any = true;
        }
        x[i] = std::clamp(x[i], lo[i], hi[i]);
      }
      if (alpha >= 1.0 || !bound_any) return;
    }
  };

  const int max_iterations = p.max_iterations > 0 ? p.max_iterations : int(4 * n + 20);
  Eigen::Index last_freed = -1;
  for (out->iterations = 0; out->iterations < max_iterations; ++out->iterations) {
    optimise_free_set();
    // KKT: a variable at its lower bound must not want to grow (gradient >= 0), one at its
    // upper bound must not want to shrink (gradient <= 0).
    const Eigen::VectorXd grad = g * x - c;
    Eigen::Index worst = -1;
    double worst_violation = tol;
    for (Eigen::Index i = 0; i < n; ++i) {
      double v = 0.0;
      if (state[size_t(i)] == Bound::kLow && lo[i] < hi[i]) v = -grad[i];
      if (state[size_t(i)] == Bound::kHigh && lo[i] < hi[i]) v = grad[i];
      if (v > worst_violation && i != last_freed) {
        worst_violation = v;
        worst = i;
      }
    }
    if (worst < 0) {
      // Nothing to free except, possibly, the variable freed last, which rebound at once: it
      // cannot move inward without making another bound variable leave (Stark and Parker's
      // anti-cycling rule); accept the point when every other condition holds.
      bool ok = true;
      if (last_freed >= 0) {
        const double g_last = grad[last_freed];
        if (state[size_t(last_freed)] == Bound::kLow && -g_last > tol) ok = false;
        if (state[size_t(last_freed)] == Bound::kHigh && g_last > tol) ok = false;
        if (!ok) {
          worst = last_freed;  // try it once more after the others settled
          last_freed = -1;
        }
      }
      if (ok) {
        out->converged = true;
        break;
      }
    }
    state[size_t(worst)] = Bound::kFree;
    last_freed = worst;
  }
  out->x.assign(x.data(), x.data() + n);
  out->residual2 = p.rows ? (a * x - b).squaredNorm() : 0.0;
  return true;
}

}  // namespace mimetic
