// The envelope LDLᵀ inside SparseLm against Eigen's dense LDLᵀ on the same matrices, with rows
// whose first entries are zero (as a band problem's inactive terms leave them) and patterns
// that change from one matrix to the next.
#include "coopnav/band/envelope_ldlt.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace coopnav {
namespace {

/// A symmetric diagonally dominant matrix in the envelope `first`, each entry zero with
/// probability `zero_share` (so rows start with zeros, or hold them inside, or both).
struct EnvelopeMatrix {
  std::vector<int> first;
  Eigen::MatrixXd dense;

  EnvelopeMatrix(const std::vector<int>& f, double zero_share, unsigned seed) : first(f) {
    const int n = static_cast<int>(f.size());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> value(-1.0, 1.0), coin(0.0, 1.0);
    dense = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      for (int j = f[i]; j < i; ++j) {
        const double v = coin(rng) < zero_share ? 0.0 : value(rng);
        dense(i, j) = dense(j, i) = v;
      }
    }
    for (int i = 0; i < n; ++i) dense(i, i) = dense.row(i).cwiseAbs().sum() + 0.5;
  }

  /// The lower triangle in `ldlt`'s storage.
  std::vector<double> stored(const EnvelopeLdlt& ldlt) const {
    std::vector<double> a(ldlt.storage(), 0.0);
    for (int i = 0; i < dense.rows(); ++i) {
      for (int j = first[i]; j <= i; ++j) a[ldlt.slot(i, j)] = dense(i, j);
    }
    return a;
  }
};

std::vector<int> randomEnvelope(int n, int max_width, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> width(0, max_width);
  std::vector<int> first(n);
  for (int i = 0; i < n; ++i) first[i] = std::max(0, i - width(rng));
  return first;
}

/// |x − x_dense|∞ / |x_dense|∞ for (A + λI) x = b.
double solveError(EnvelopeLdlt* ldlt, const EnvelopeMatrix& m, double lambda) {
  const int n = static_cast<int>(m.first.size());
  const std::vector<double> a = m.stored(*ldlt);
  ldlt->narrowTo(a.data());
  EXPECT_TRUE(ldlt->factorize(a.data(), lambda));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  Eigen::VectorXd x;
  ldlt->solve(b, &x);
  const Eigen::MatrixXd shifted = m.dense + lambda * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd ref = shifted.ldlt().solve(b);
  return (x - ref).lpNorm<Eigen::Infinity>() / ref.lpNorm<Eigen::Infinity>();
}

TEST(EnvelopeLdltTest, SolvesAsTheDenseFactorisationDoes) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::vector<int> first = randomEnvelope(60, 12, seed);
    EnvelopeLdlt ldlt;
    ldlt.setPattern(first);
    // No zeros, some, most: rows that start late and rows with holes.
    for (double zeros : {0.0, 0.3, 0.8}) {
      const EnvelopeMatrix m(first, zeros, 100 + seed);
      EXPECT_LT(solveError(&ldlt, m, 0.0), 1e-12) << "seed " << seed << " zeros " << zeros;
      EXPECT_LT(solveError(&ldlt, m, 2.5), 1e-12) << "seed " << seed << " zeros " << zeros;
    }
  }
}

TEST(EnvelopeLdltTest, RowsWidenAgainWhenTheirLeadingZerosFillIn) {
  // One pattern, matrices in turn: the second has entries where the first's rows began with
  // zeros, so the narrowing must come from the envelope each time, not from the last matrix.
  const std::vector<int> first = randomEnvelope(50, 10, 7);
  EnvelopeLdlt ldlt;
  ldlt.setPattern(first);
  const EnvelopeMatrix sparse(first, 0.9, 1), full(first, 0.0, 2);
  EXPECT_LT(solveError(&ldlt, sparse, 0.1), 1e-12);
  EXPECT_LT(solveError(&ldlt, full, 0.1), 1e-12);
  EXPECT_LT(solveError(&ldlt, sparse, 0.1), 1e-12);
}

TEST(EnvelopeLdltTest, DiagonalOnlyRowsAndAWholeDiagonalMatrix) {
  std::vector<int> first(30);
  for (int i = 0; i < 30; ++i) first[i] = std::max(0, i - 5);
  EnvelopeLdlt ldlt;
  ldlt.setPattern(first);
  EXPECT_LT(solveError(&ldlt, EnvelopeMatrix(first, 1.0, 3), 0.0), 1e-15);
}

TEST(EnvelopeLdltTest, RefusesAMatrixThatIsNotPositiveDefinite) {
  const std::vector<int> first = {0, 0, 1};
  EnvelopeLdlt ldlt;
  ldlt.setPattern(first);
  // [[1, 2, 0], [2, 1, 0], [0, 0, 1]]: eigenvalues 3, -1, 1.
  std::vector<double> a(ldlt.storage(), 0.0);
  a[ldlt.slot(0, 0)] = 1.0;
  a[ldlt.slot(1, 0)] = 2.0;
  a[ldlt.slot(1, 1)] = 1.0;
  a[ldlt.slot(2, 2)] = 1.0;
  ldlt.narrowTo(a.data());
  EXPECT_FALSE(ldlt.factorize(a.data(), 0.0));
  // Damped enough, the same matrix is positive definite.
  EXPECT_TRUE(ldlt.factorize(a.data(), 1.5));
}

}  // namespace
}  // namespace coopnav
