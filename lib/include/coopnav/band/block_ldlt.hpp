#pragma once
/// @file The linear solver inside SparseLm (sparse_lm.hpp): block LDLᵀ of a symmetric positive
/// definite matrix whose unknowns come in small nodes (a band's poses and time differences), on
/// the pattern of the tiles that are not zero at each linearisation. Its own header so that the
/// factorisation is tested on its own (test/unit/band/block_ldlt_test.cpp), not only through the
/// iterates of a solve.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace coopnav {

/// A = L D Lᵀ with L unit block lower triangular and D block diagonal, node by node ("up-looking":
/// row v of L from the rows above it; Davis, "Direct methods for sparse linear systems", 2006,
/// ch. 4), on the elimination tree of the tiles of A that are not zero.
/// Most of a band problem's terms are hinges inside their limits at any one step, with exactly
/// zero Jacobians; their tiles stay zero and create no fill. Nodes are eliminated in the order
/// given (a fill-reducing one: SparseLm orders by minimum degree).
/// Why this factorisation: in one bench_band run against a dense-row envelope LDLᵀ on Sloan's
/// profile-reducing order of the same matrices, one human took 12 % less time at p50 (13 % at
/// p99), five humans 23 % (31 %).
class BlockLdlt {
 public:
  static constexpr int kMaxNodeSize = 6;

  /// Node v has sizes[v] unknowns (1..kMaxNodeSize), numbered after node v − 1's. Its tiles
  /// below the diagonal are A(v, u) for u in lower[start[v] .. start[v + 1]), ascending, u < v.
  void setStructure(std::vector<int> sizes, std::vector<int> start, std::vector<int> lower);

  /// Doubles in A's storage: every tile, row-major.
  std::size_t storage() const { return storage_; }
  /// Storage offset of the diagonal tile of v (sizes[v]², its lower triangle is read).
  int diagonalTile(int v) const { return diag_[v]; }
  /// Storage offset of tile A(v, u), u < v (sizes[v] × sizes[u]); -1 when not in the structure.
  int tile(int v, int u) const;
  int nodeSize(int v) const { return size_[v]; }
  /// First unknown of node v.
  int offset(int v) const { return offset_[v]; }
  int unknowns() const { return offset_.empty() ? 0 : offset_.back(); }

  /// A = 0 for its next assembly, given that the last analyze() saw A as it is: only the tiles
  /// it found not zero and the diagonal are cleared (the rest are zero already).
  void clear(double* a) const;

  /// The pattern of A's values for the factorize() calls on this A: the tiles not all zero,
  /// and their elimination tree.
  void analyze(const double* a);

  /// Factorises A + λI (A as the last analyze() saw its pattern), row by row in node order;
  /// false when not numerically positive definite.
  bool factorize(const double* a, double lambda);

  /// x = (L D Lᵀ)⁻¹ b after a successful factorize().
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const;

  /// Tiles of L below the diagonal on the last analyze()'s pattern (tests, benchmarks).
  std::size_t factorTiles() const { return pattern_.size(); }

 private:
  static constexpr double kMinPivot = 1e-300;
  /// D(v)⁻¹ (row-major, full) from D(v)'s lower half; false when not positive definite.
  bool invertDiagonal(int v, double* d);
  /// Row v of L and D(v)⁻¹; false when D(v) is not positive definite.
  bool factorRow(int v, const double* a, double lambda);
  /// The solve's three passes, one row each: z_v −= L(v, ·) z; z_v = D(v)⁻¹ z_v; z_u −= L(v, u)ᵀ
  /// z_v.
  void forwardRow(int v, double* z) const;
  void scaleRow(int v, double* z) const;
  void backwardRow(int v, double* z) const;
  /// Row v's tile L(v, u) from the workspace, its updates of row v's tiles right of u and of
  /// D(v); SV, SU: the node sizes if fixed, else 0.
  template <int SV, int SU>
  void eliminate(int v, int u, int pos, double* d);

  int n_{0};
  std::vector<int> size_;
  std::vector<int> offset_;  ///< n + 1 entries
  std::vector<int> start_, lower_, tile_;
  std::vector<int> diag_;
  std::size_t storage_{0};

  // analyze(): A's tiles that are not zero, as indices into lower_, and the elimination tree.
  std::vector<int> nz_start_, nz_;
  std::vector<int> parent_;

  // analyze(): L's pattern by row (pattern_[row_start_[v] ..], ascending) and its tiles stored
  // by column (column u at [col_start_[u], col_start_[u + 1]), rows ascending).
  std::vector<int> row_start_, pattern_;
  std::vector<int> entry_pos_;  ///< per row pattern entry: its place in the column storage
  std::vector<int> row_val_;    ///< per row pattern entry: offset of its tile's values
  std::vector<int> col_start_, col_count_;
  std::vector<int> entry_row_;  ///< per place: row node
  std::vector<int> entry_val_;  ///< per place: offset of the tile's values in lvals_
  std::vector<double> lvals_;
  std::vector<int> dinv_;  ///< offset of D(v)⁻¹ in dvals_
  std::vector<double> dvals_;

  // Scratch.
  std::vector<double> work_;  ///< row v's tiles Y(v, ·), transposed: kMaxNodeSize per unknown
  std::vector<int> mark_;
};

}  // namespace coopnav
