// The block LDLᵀ inside SparseLm against Eigen's dense LDLᵀ on the same matrices: nodes of mixed
// sizes, tiles that are zero (as a band problem's inactive terms leave them) and patterns that
// change from one matrix to the next.
#include "coopnav/band/block_ldlt.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace coopnav {
namespace {

/// A structure of n nodes of 1 or 3 unknowns (a band's time differences and poses), each tied to
/// a few nodes shortly before it and, now and then, to one far before (agents meeting in time).
struct Structure {
  std::vector<int> sizes, start, lower;
};

Structure randomStructure(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> size(0, 1), near(1, 4), far(0, 9);
  Structure s;
  s.start.push_back(0);
  for (int v = 0; v < n; ++v) {
    s.sizes.push_back(size(rng) ? 3 : 1);
    std::vector<int> l;
    for (int u = std::max(0, v - near(rng)); u < v; ++u) l.push_back(u);
    if (v > 10 && far(rng) == 0) l.push_back(std::uniform_int_distribution<int>(0, v - 6)(rng));
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    s.lower.insert(s.lower.end(), l.begin(), l.end());
    s.start.push_back(static_cast<int>(s.lower.size()));
  }
  return s;
}

/// A symmetric diagonally dominant matrix on the structure, each tile zero with probability
/// `zero_share`, in `ldlt`'s storage and dense.
struct TiledMatrix {
  std::vector<double> stored;
  Eigen::MatrixXd dense;
  TiledMatrix(const Structure& s, const BlockLdlt& ldlt, double zero_share, unsigned seed) {
    const int n = ldlt.unknowns();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> value(-1.0, 1.0), coin(0.0, 1.0);
    dense = Eigen::MatrixXd::Zero(n, n);
    const int nodes = static_cast<int>(s.sizes.size());
    for (int v = 0; v < nodes; ++v) {
      for (int k = s.start[v]; k < s.start[v + 1]; ++k) {
        if (coin(rng) < zero_share) continue;
        const int u = s.lower[k];
        for (int r = 0; r < s.sizes[v]; ++r) {
          for (int c = 0; c < s.sizes[u]; ++c) {
            const double x = value(rng);
            dense(ldlt.offset(v) + r, ldlt.offset(u) + c) = x;
            dense(ldlt.offset(u) + c, ldlt.offset(v) + r) = x;
          }
        }
      }
      for (int r = 0; r < s.sizes[v]; ++r) {
        for (int c = 0; c < r; ++c) {
          const double x = value(rng);
          dense(ldlt.offset(v) + r, ldlt.offset(v) + c) = x;
          dense(ldlt.offset(v) + c, ldlt.offset(v) + r) = x;
        }
      }
    }
    for (int i = 0; i < n; ++i) dense(i, i) = dense.row(i).cwiseAbs().sum() + 0.5;
    stored.assign(ldlt.storage(), 0.0);
    for (int v = 0; v < nodes; ++v) {
      const int sv = s.sizes[v];
      for (int r = 0; r < sv; ++r) {
        for (int c = 0; c <= r; ++c) {
          stored[ldlt.diagonalTile(v) + r * sv + c] = dense(ldlt.offset(v) + r, ldlt.offset(v) + c);
        }
      }
      for (int k = s.start[v]; k < s.start[v + 1]; ++k) {
        const int u = s.lower[k], su = s.sizes[u], t = ldlt.tile(v, u);
        for (int r = 0; r < sv; ++r) {
          for (int c = 0; c < su; ++c)
            stored[t + r * su + c] = dense(ldlt.offset(v) + r, ldlt.offset(u) + c);
        }
      }
    }
  }
};

BlockLdlt make(const Structure& s) {
  BlockLdlt ldlt;
  ldlt.setStructure(s.sizes, s.start, s.lower);
  return ldlt;
}

/// |x − x_dense|∞ / |x_dense|∞ for (A + λI) x = b.
double solveError(BlockLdlt* ldlt, const TiledMatrix& m, double lambda) {
  const int n = ldlt->unknowns();
  ldlt->analyze(m.stored.data());
  EXPECT_TRUE(ldlt->factorize(m.stored.data(), lambda));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  Eigen::VectorXd x;
  ldlt->solve(b, &x);
  const Eigen::MatrixXd shifted = m.dense + lambda * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd ref = shifted.ldlt().solve(b);
  return (x - ref).lpNorm<Eigen::Infinity>() / ref.lpNorm<Eigen::Infinity>();
}

TEST(BlockLdltTest, SolvesAsTheDenseFactorisationDoes) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const Structure s = randomStructure(60, seed);
    BlockLdlt ldlt = make(s);
    for (double zeros : {0.0, 0.3, 0.8}) {
      const TiledMatrix m(s, ldlt, zeros, 100 + seed);
      EXPECT_LT(solveError(&ldlt, m, 0.0), 1e-12) << "seed " << seed << " zeros " << zeros;
      EXPECT_LT(solveError(&ldlt, m, 2.5), 1e-12) << "seed " << seed << " zeros " << zeros;
    }
  }
}

TEST(BlockLdltTest, ZeroTilesMakeNoFill) {
  // A chain tied to its first node: with the tie, eliminating node 0 first fills every row;
  // with the tie's tiles zero, L has only the chain.
  Structure s;
  s.start.push_back(0);
  const int n = 20;
  for (int v = 0; v < n; ++v) {
    s.sizes.push_back(3);
    if (v >= 1) s.lower.push_back(0);
    if (v >= 2) s.lower.push_back(v - 1);
    s.start.push_back(static_cast<int>(s.lower.size()));
  }
  BlockLdlt ldlt = make(s);
  TiledMatrix tied(s, ldlt, 0.0, 5);
  EXPECT_LT(solveError(&ldlt, tied, 0.0), 1e-12);
  EXPECT_EQ(ldlt.factorTiles(), static_cast<std::size_t>((n - 1) * n / 2));
  TiledMatrix chain = tied;
  for (int v = 2; v < n; ++v) {
    const int t = ldlt.tile(v, 0);
    std::fill(chain.stored.begin() + t, chain.stored.begin() + t + 9, 0.0);
    chain.dense.block(3 * v, 0, 3, 3).setZero();
    chain.dense.block(0, 3 * v, 3, 3).setZero();
  }
  EXPECT_LT(solveError(&ldlt, chain, 0.0), 1e-12);
  EXPECT_EQ(ldlt.factorTiles(), static_cast<std::size_t>(n - 1));
  // And the fill comes back with the tie.
  EXPECT_LT(solveError(&ldlt, tied, 0.0), 1e-12);
  EXPECT_EQ(ldlt.factorTiles(), static_cast<std::size_t>((n - 1) * n / 2));
}

TEST(BlockLdltTest, ClearLeavesEveryTileZero) {
  // clear() touches only the diagonal and the tiles analyze() found not zero: the others must
  // be zero already, so after it the whole storage is.
  const Structure s = randomStructure(40, 11);
  BlockLdlt ldlt = make(s);
  TiledMatrix m(s, ldlt, 0.5, 12);
  ldlt.analyze(m.stored.data());
  ldlt.clear(m.stored.data());
  EXPECT_TRUE(std::all_of(m.stored.begin(), m.stored.end(), [](double x) { return x == 0.0; }));
}

TEST(BlockLdltTest, DiagonalOnly) {
  const Structure s = randomStructure(30, 3);
  BlockLdlt ldlt = make(s);
  EXPECT_LT(solveError(&ldlt, TiledMatrix(s, ldlt, 1.0, 3), 0.0), 1e-15);
  EXPECT_EQ(ldlt.factorTiles(), 0u);
}

TEST(BlockLdltTest, RefusesAMatrixThatIsNotPositiveDefinite) {
  // Nodes of one unknown: [[1, 2, 0], [2, 1, 0], [0, 0, 1]], eigenvalues 3, -1, 1.
  BlockLdlt ldlt;
  ldlt.setStructure({1, 1, 1}, {0, 0, 1, 1}, {0});
  std::vector<double> a(ldlt.storage(), 0.0);
  a[ldlt.diagonalTile(0)] = 1.0;
  a[ldlt.tile(1, 0)] = 2.0;
  a[ldlt.diagonalTile(1)] = 1.0;
  a[ldlt.diagonalTile(2)] = 1.0;
  ldlt.analyze(a.data());
  EXPECT_FALSE(ldlt.factorize(a.data(), 0.0));
  // Damped enough, the same matrix is positive definite, and a failed call left nothing behind.
  EXPECT_TRUE(ldlt.factorize(a.data(), 1.5));
  Eigen::VectorXd x;
  ldlt.solve(Eigen::Vector3d(1.0, 0.0, 2.0), &x);
  Eigen::Matrix3d dense;
  dense << 2.5, 2.0, 0.0, 2.0, 2.5, 0.0, 0.0, 0.0, 2.5;
  EXPECT_LT((dense * x - Eigen::Vector3d(1.0, 0.0, 2.0)).norm(), 1e-14);
}

TEST(BlockLdltTest, RejectsMalformedStructures) {
  BlockLdlt ldlt;
  EXPECT_THROW(ldlt.setStructure({1, 1}, {0, 0, 1}, {1}), std::logic_error);  // u >= v
  EXPECT_THROW(ldlt.setStructure({7}, {0, 0}, {}), std::logic_error);         // too big
  EXPECT_THROW(ldlt.setStructure({1, 1}, {0, 0}, {}), std::logic_error);      // lists disagree
}

}  // namespace
}  // namespace coopnav
