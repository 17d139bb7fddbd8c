// tests/fitting/box_least_squares_test.cpp: SolveBoxLeastSquares (fitting/box_least_squares.h)
// against answers by hand, the KKT conditions, and a second method (projected gradient
// descent run to convergence).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "fitting/box_least_squares.h"

namespace mimetic {
namespace {

struct Problem {
  std::vector<double> a, b, lo, hi;
  size_t rows = 0, cols = 0;
  double ridge = 0.0;
  BoxLeastSquaresProblem View() const {
    return {.a = a.data(), .b = b.data(), .rows = rows, .cols = cols, .lo = lo.data(),
            .hi = hi.data(), .ridge = ridge};
  }
};

Problem Random(size_t rows, size_t cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Problem p;
  p.rows = rows;
  p.cols = cols;
  p.a.resize(rows * cols);
  for (double& v : p.a) v = n(rng);
  p.b.assign(rows, 0.0);
  p.lo.assign(cols, 0.0);
  p.hi.assign(cols, 1.0);
  return p;
}

void SetTarget(Problem* p, const std::vector<double>& x) {
  for (size_t r = 0; r < p->rows; ++r) {
    double s = 0;
    for (size_t c = 0; c < p->cols; ++c) s += p->a[r * p->cols + c] * x[c];
    p->b[r] = s;
  }
}

// The second method: projected gradient descent with step 1/L, L = |A^T A|_F + ridge (an upper
// bound of the largest eigenvalue), run long enough to converge on these small problems.
std::vector<double> ProjectedGradient(const Problem& p, int iterations) {
  std::vector<double> g(p.cols * p.cols, 0.0), c(p.cols, 0.0), x(p.cols, 0.0);
  for (size_t r = 0; r < p.rows; ++r)
    for (size_t i = 0; i < p.cols; ++i) {
      c[i] += p.a[r * p.cols + i] * p.b[r];
      for (size_t j = 0; j < p.cols; ++j) g[i * p.cols + j] += p.a[r * p.cols + i] * p.a[r * p.cols + j];
    }
  double l = 0;
  for (size_t i = 0; i < p.cols; ++i) g[i * p.cols + i] += p.ridge;
  for (double v : g) l += v * v;
  l = std::sqrt(l);
  for (size_t i = 0; i < p.cols; ++i) x[i] = std::clamp(0.0, p.lo[i], p.hi[i]);
  for (int it = 0; it < iterations; ++it) {
    std::vector<double> grad(p.cols);
    for (size_t i = 0; i < p.cols; ++i) {
      double s = -c[i];
      for (size_t j = 0; j < p.cols; ++j) s += g[i * p.cols + j] * x[j];
      grad[i] = s;
    }
    for (size_t i = 0; i < p.cols; ++i) x[i] = std::clamp(x[i] - grad[i] / l, p.lo[i], p.hi[i]);
  }
  return x;
}

TEST(BoxLeastSquares, OneUnknownByHand) {
  // |x - 3|^2 + |x - 1|^2 is least at x = 2; with x in [0, 1] the answer is the bound 1.
  Problem p{.a = {1, 1}, .b = {3, 1}, .lo = {0}, .hi = {1}, .rows = 2, .cols = 1};
  BoxLeastSquaresResult r;
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r)) << r.error;
  EXPECT_TRUE(r.converged);
  EXPECT_DOUBLE_EQ(r.x[0], 1.0);
  EXPECT_DOUBLE_EQ(r.residual2, 4.0 + 0.0);  // (1 - 3)^2 + (1 - 1)^2
  p.hi = {5};
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r));
  EXPECT_NEAR(r.x[0], 2.0, 1e-12);
  EXPECT_NEAR(r.residual2, 2.0, 1e-12);
  // Ridge: (2 + k) x = 4  ->  x = 4 / (2 + k).
  p.ridge = 2.0;
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r));
  EXPECT_NEAR(r.x[0], 1.0, 1e-12);
  p.b = {-3, -1};  // least at -2: the lower bound 0
  p.ridge = 0.0;
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r));
  EXPECT_EQ(r.x[0], 0.0);
}

TEST(BoxLeastSquares, RecoversInteriorActivations) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    Problem p = Random(60, 12, seed);
    std::vector<double> truth(12);
    for (size_t i = 0; i < 12; ++i) truth[i] = 0.1 + 0.8 * double(i) / 11.0;
    SetTarget(&p, truth);
    BoxLeastSquaresResult r;
    ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r)) << r.error;
    EXPECT_TRUE(r.converged);
    for (size_t i = 0; i < 12; ++i) EXPECT_NEAR(r.x[i], truth[i], 1e-9) << seed << " " << i;
    EXPECT_LT(r.residual2, 1e-16);
  }
}

TEST(BoxLeastSquares, ActiveBoundsMatchKktAndProjectedGradient) {
  for (unsigned seed = 10; seed <= 17; ++seed) {
    Problem p = Random(40, 8, seed);
    // A target outside the box: several unknowns end on a bound.
    std::vector<double> truth = {-0.7, 0.3, 1.8, 0.5, -0.2, 1.2, 0.9, 2.5};
    SetTarget(&p, truth);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.05);
    for (double& v : p.b) v += noise(rng);
    BoxLeastSquaresResult r;
    ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r)) << r.error;
    EXPECT_TRUE(r.converged);
    const std::vector<double> ref = ProjectedGradient(p, 200000);
    int at_bound = 0;
    for (size_t i = 0; i < p.cols; ++i) {
      EXPECT_NEAR(r.x[i], ref[i], 1e-6) << seed << " " << i;
      EXPECT_GE(r.x[i], 0.0);
      EXPECT_LE(r.x[i], 1.0);
      at_bound += r.x[i] == 0.0 || r.x[i] == 1.0;
    }
    EXPECT_GE(at_bound, 2) << seed;
    // KKT: gradient of |Ax - b|^2 / 2 is >= 0 at the lower bound, <= 0 at the upper, ~0 inside.
    for (size_t i = 0; i < p.cols; ++i) {
      double grad = 0;
      for (size_t row = 0; row < p.rows; ++row) {
        double res = -p.b[row];
        for (size_t j = 0; j < p.cols; ++j) res += p.a[row * p.cols + j] * r.x[j];
        grad += p.a[row * p.cols + i] * res;
      }
      if (r.x[i] == 0.0) EXPECT_GE(grad, -1e-8);
      else if (r.x[i] == 1.0) EXPECT_LE(grad, 1e-8);
      else EXPECT_NEAR(grad, 0.0, 1e-8);
    }
  }
}

TEST(BoxLeastSquares, DependentAndZeroColumnsStayFinite) {
  // Columns 0 and 1 are equal, column 2 is zero: any split of 0.8 between x0 and x1 is a
  // least-squares solution; the answer must be one of them, finite, and x2 stays at 0.
  Problem p{.a = {1, 1, 0, 2, 2, 0, -1, -1, 0}, .b = {0.8, 1.6, -0.8}, .lo = {0, 0, 0},
            .hi = {1, 1, 1}, .rows = 3, .cols = 3};
  BoxLeastSquaresResult r;
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r)) << r.error;
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x[0] + r.x[1], 0.8, 1e-9);
  EXPECT_EQ(r.x[2], 0.0);
  EXPECT_NEAR(r.residual2, 0.0, 1e-15);
}

TEST(BoxLeastSquares, RefusesBadProblemsWithAReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Problem good{.a = {1, 1}, .b = {3, 1}, .lo = {0}, .hi = {1}, .rows = 2, .cols = 1};
  struct Case {
    const char* what;
    Problem p;
    const char* message;
  };
  std::vector<Case> cases;
  Problem q = good;
  q.a[1] = nan;
  cases.push_back({"NaN in A", q, "A has a non-finite entry"});
  q = good;
  q.b[0] = INFINITY;
  cases.push_back({"inf in b", q, "b has a non-finite entry"});
  q = good;
  q.lo = {2};
  cases.push_back({"lo > hi", q, "lower bound above upper bound for unknown 0"});
  q = good;
  q.ridge = -1;
  cases.push_back({"negative ridge", q, "ridge must be finite and >= 0"});
  q = good;
  q.cols = 0;
  cases.push_back({"no unknowns", q, "no unknowns"});
  for (const Case& c : cases) {
    BoxLeastSquaresResult r;
    EXPECT_FALSE(SolveBoxLeastSquares(c.p.View(), &r)) << c.what;
    EXPECT_NE(r.error.find(c.message), std::string::npos) << c.what << ": " << r.error;
    EXPECT_TRUE(r.x.empty());
  }
}

TEST(BoxLeastSquares, SameInputSameBits) {
  Problem p = Random(50, 10, 99);
  SetTarget(&p, {1.4, -0.3, 0.2, 0.7, 0.9, 1.1, 0.0, 0.5, 0.3, -1.0});
  BoxLeastSquaresResult r1, r2;
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r1));
  ASSERT_TRUE(SolveBoxLeastSquares(p.View(), &r2));
  EXPECT_EQ(r1.x, r2.x);
}

}  // namespace
}  // namespace mimetic
