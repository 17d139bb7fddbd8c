// fitting/box_least_squares.h: linear least squares with box bounds,
//   minimise |A x - b|^2 + ridge |x|^2  subject to  lo <= x <= hi,
// the core of `mimetic solve` (muscle displacement is linear in the activations, so the
// activations closest to a target shape are a bounded linear least-squares problem).
//
// This work is based on: P. B. Stark and R. L. Parker, "Bounded-Variable Least-Squares: an
// Algorithm and Applications", Computational Statistics 10 (1995) 129-141 (the active-set
// loop below), which extends Lawson and Hanson's NNLS ("Solving Least Squares Problems",
// 1974, ch. 23) from x >= 0 to two-sided bounds. Solved on the normal equations (A^T A is
// cols x cols, and cols, the muscle count, is small), with Eigen's LDLT on the free set.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace mimetic {

struct BoxLeastSquaresProblem {
  // A, row-major: rows x cols. b: rows. lo, hi: cols each, lo[i] <= hi[i].
  const double* a = nullptr;
  const double* b = nullptr;
  size_t rows = 0, cols = 0;
  const double* lo = nullptr;
  const double* hi = nullptr;
  double ridge = 0.0;  // >= 0: Tikhonov weight on |x|^2 (0 = plain least squares)
  int max_iterations = 0;  // 0 = 4 * cols + 20 outer steps
};

struct BoxLeastSquaresResult {
  std::vector<double> x;      // cols, within [lo, hi]
  double residual2 = 0.0;     // |A x - b|^2 (without the ridge term)
  int iterations = 0;         // outer (freeing) steps taken
  bool converged = false;     // the KKT conditions hold to a relative 1e-10
  std::string error;          // why the problem was refused (empty on success)
};

// Solves the problem. Returns false (with `error` set and x empty) for: null arrays with
// non-zero sizes, cols == 0, a non-finite entry in A, b, lo or hi, lo > hi, a negative or
// non-finite ridge. A column of zeros leaves its variable where the start puts it (the bound
// nearest 0). Returns true otherwise; `converged` is false only when max_iterations ran out
// (x is then the best feasible point found). Deterministic.
bool SolveBoxLeastSquares(const BoxLeastSquaresProblem& problem, BoxLeastSquaresResult* out);

}  // namespace mimetic
