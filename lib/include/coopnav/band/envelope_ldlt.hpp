#pragma once
/// @file The linear solver inside SparseLm (sparse_lm.hpp): LDLᵀ of a symmetric positive
/// definite matrix in row-envelope ("profile", skyline) storage. Its own header so that the
/// factorisation is tested on its own (test/unit/band/envelope_ldlt_test.cpp), not only through
/// the iterates of a solve.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace coopnav {

/// Row i holds columns first(i)..i contiguously. Cholesky creates no fill outside the envelope,
/// so the pattern is fixed by the ordering alone, and the work is dense dot products of row
/// segments (George & Liu, "Computer solution of large sparse positive definite systems", 1981,
/// ch. 4). With a profile-reducing order of the band problem (Sloan's, sparse_lm.cpp) the
/// envelope is the time slices' width, and this is 2-4x faster than Eigen's scalar simplicial
/// LDLᵀ (bench_band).
class EnvelopeLdlt {
 public:
  /// first[i] <= i: leftmost column of row i.
  void setPattern(std::vector<int> first);
  /// Entries of the storage that A and the factor use.
  std::size_t storage() const { return work_.size(); }
  /// Storage index of entry (i, j), first(i) <= j <= i.
  int slot(int i, int j) const { return base_[i] + j; }

  /// Narrows every row to A's first entry that is not zero, for the factorize() calls on this
  /// A: L has no non-zero left of A's first in any row (w_j in factorize() stays exactly 0
  /// while a_ij is), so the envelope of A's own values is exact. The pattern is that of every
  /// term that could become active; at any one step most are not (a hinge inside its limits has
  /// an exactly zero Jacobian): bench_band, 2026-12-03, this skips 59 % of the multiply-adds for
  /// one human and 53 % for five. The results differ from the full envelope's only in rounding
  /// (the partial sums group the products differently).
  void narrowTo(const double* a);

  /// Sets A to zero for its next assembly: only from each row's first non-zero at the last
  /// narrowTo(A) on, since left of it A is zero already (half the envelope's stores for five
  /// humans).
  void clear(double* a) const;

  /// Factorises A + λI (A in this storage, its rows as the last narrowTo(A) left them); false
  /// when not numerically positive definite.
  bool factorize(const double* a, double lambda);

  /// x = (L D Lᵀ)⁻¹ b after a successful factorize().
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const;

 private:
  static constexpr double kMinPivot = 1e-300;
  std::vector<int> first_;
  std::vector<int> lead_;     ///< per row, A's first non-zero at the last narrowTo() (>= first_)
  std::vector<int> base_;     ///< row i's entry (i, j) is at base_[i] + j (rows stored in order)
  std::vector<double> work_;  ///< L below the diagonal (unit diagonal implied)
  std::vector<double> d_;
  std::vector<double> inv_d_;  ///< 1 / d_: one division per row instead of one per entry
};

}  // namespace coopnav
