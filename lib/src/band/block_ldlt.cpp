#include "coopnav/band/block_ldlt.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

/// The kernels' loops run over a node's few unknowns, fixed at compile time where the sizes are
/// template arguments: unrolled, their indices are constants (-O2 does not unroll them itself).
#define COOPNAV_UNROLL _Pragma("GCC unroll 6")

namespace coopnav {

void BlockLdlt::setStructure(std::vector<int> sizes, std::vector<int> start,
                             std::vector<int> lower) {
  n_ = static_cast<int>(sizes.size());
  if (static_cast<int>(start.size()) != n_ + 1 || start.back() != static_cast<int>(lower.size()))
    throw std::logic_error("BlockLdlt: structure lists disagree");
  size_ = std::move(sizes);
  start_ = std::move(start);
  lower_ = std::move(lower);
  offset_.assign(n_ + 1, 0);
  diag_.assign(n_, 0);
  tile_.assign(lower_.size(), 0);
  int t = 0;
  for (int v = 0; v < n_; ++v) {
    const int s = size_[v];
    if (s < 1 || s > kMaxNodeSize) throw std::logic_error("BlockLdlt: node size out of range");
    offset_[v + 1] = offset_[v] + s;
    diag_[v] = t;
    t += s * s;
    for (int k = start_[v]; k < start_[v + 1]; ++k) {
      const int u = lower_[k];
      if (u < 0 || u >= v || (k > start_[v] && lower_[k - 1] >= u))
        throw std::logic_error("BlockLdlt: lower neighbours must ascend below the node");
      tile_[k] = t;
      t += s * size_[u];
    }
  }
  storage_ = static_cast<std::size_t>(t);
  nz_start_.assign(n_ + 1, 0);
  nz_.clear();
  parent_.assign(n_, -1);
  row_start_.assign(n_ + 1, 0);
  col_start_.assign(n_ + 1, 0);
  col_count_.assign(n_, 0);
  pattern_.clear();
  entry_pos_.clear();
  row_val_.clear();
  entry_row_.clear();
  entry_val_.clear();
  dinv_.assign(n_, 0);
  int d = 0;
  for (int v = 0; v < n_; ++v) {
    dinv_[v] = d;
    d += size_[v] * size_[v];
  }
  dvals_.assign(d, 0.0);
  work_.assign(static_cast<std::size_t>(kMaxNodeSize) * unknowns(), 0.0);
  mark_.assign(n_, -1);
}

int BlockLdlt::tile(int v, int u) const {
  const auto first = lower_.begin() + start_[v], last = lower_.begin() + start_[v + 1];
  const auto it = std::lower_bound(first, last, u);
  return it != last && *it == u ? tile_[it - lower_.begin()] : -1;
}

void BlockLdlt::clear(double* a) const {
  for (int v = 0; v < n_; ++v) std::fill(a + diag_[v], a + diag_[v] + size_[v] * size_[v], 0.0);
  for (int v = 0; v < n_; ++v) {
    for (int q = nz_start_[v]; q < nz_start_[v + 1]; ++q) {
      const int k = nz_[q];
      std::fill(a + tile_[k], a + tile_[k] + size_[v] * size_[lower_[k]], 0.0);
    }
  }
}

void BlockLdlt::analyze(const double* a) {
  nz_.clear();
  std::vector<int>& ancestor = mark_;
  ancestor.assign(n_, -1);
  for (int v = 0; v < n_; ++v) {
    nz_start_[v] = static_cast<int>(nz_.size());
    parent_[v] = -1;
    for (int k = start_[v]; k < start_[v + 1]; ++k) {
      const double* t = a + tile_[k];
      const int m = size_[v] * size_[lower_[k]];
      if (std::all_of(t, t + m, [](double x) { return x == 0.0; })) continue;
      nz_.push_back(k);
      // The elimination tree, with path compression (Liu 1986; Davis 2006, ch. 4).
      for (int x = lower_[k]; x != -1 && x < v;) {
        const int next = ancestor[x];
        ancestor[x] = v;
        if (next == -1) parent_[x] = v;
        x = next;
      }
    }
  }
  nz_start_[n_] = static_cast<int>(nz_.size());
  // L's pattern, row by row: every node on the tree path from a non-zero tile's column up to
  // the row's node (Davis 2006, ch. 4), ascending (a topological order of the tree: every update
  // of a tile comes from a column left of it).
  std::fill(mark_.begin(), mark_.end(), -1);
  std::fill(col_count_.begin(), col_count_.end(), 0);
  pattern_.clear();
  for (int v = 0; v < n_; ++v) {
    row_start_[v] = static_cast<int>(pattern_.size());
    mark_[v] = v;
    for (int q = nz_start_[v]; q < nz_start_[v + 1]; ++q) {
      for (int x = lower_[nz_[q]]; mark_[x] != v; x = parent_[x]) {
        mark_[x] = v;
        pattern_.push_back(x);
        ++col_count_[x];
      }
    }
    std::sort(pattern_.begin() + row_start_[v], pattern_.end());
  }
  row_start_[n_] = static_cast<int>(pattern_.size());
  // Tiles stored by column, rows ascending: a column's tiles above row v are contiguous when
  // row v needs them. entry_pos_[k]: where row pattern entry k's tile sits.
  const std::size_t m = pattern_.size();
  col_start_[0] = 0;
  for (int u = 0; u < n_; ++u) col_start_[u + 1] = col_start_[u] + col_count_[u];
  std::copy(col_start_.begin(), col_start_.end() - 1, col_count_.begin());  // fill pointers
  entry_pos_.resize(m);
  entry_row_.resize(m);
  entry_val_.resize(m);
  for (int v = 0; v < n_; ++v) {
    for (int k = row_start_[v]; k < row_start_[v + 1]; ++k) {
      const int pos = col_count_[pattern_[k]]++;
      entry_pos_[k] = pos;
      entry_row_[pos] = v;
    }
  }
  int vals = 0;
  for (int u = 0; u < n_; ++u) {
    for (int pos = col_start_[u]; pos < col_start_[u + 1]; ++pos) {
      entry_val_[pos] = vals;
      vals += size_[entry_row_[pos]] * size_[u];
    }
  }
  row_val_.resize(m);
  for (std::size_t k = 0; k < m; ++k) row_val_[k] = entry_val_[entry_pos_[k]];
  lvals_.resize(vals);
}

namespace {

/// Sizes known at compile time (a band problem's nodes have 4 or 1 unknowns), or 0: taken from
/// the run-time argument (never above kMaxNodeSize: setStructure() checks, and the bound lets
/// the compiler see the scratch arrays are large enough). The kernels are the same loops either
/// way; fixed sizes unroll them.
template <int kFixed>
inline int sizeOf(int runtime) {
  return kFixed > 0 ? kFixed : std::min(runtime, BlockLdlt::kMaxNodeSize);
}

/// Tile (v, x) −= Y L(x, u)ᵀ, with Yᵀ (su × sv), L(x, u) (sx × su) and the tile transposed in
/// w: every inner loop runs over contiguous entries of v's rows.
template <int SV, int SU, int SX>
inline void scatterUpdate(const double* __restrict yt, const double* __restrict lx,
                          double* __restrict w, int sv_rt, int su_rt, int sx_rt) {
  const int sv = sizeOf<SV>(sv_rt), su = sizeOf<SU>(su_rt), sx = sizeOf<SX>(sx_rt);
  COOPNAV_UNROLL
  for (int c = 0; c < sx; ++c) {
    COOPNAV_UNROLL
    for (int k = 0; k < su; ++k) {
      const double f = lx[c * su + k];
      COOPNAV_UNROLL
      for (int r = 0; r < sv; ++r) w[c * sv + r] -= yt[k * sv + r] * f;
    }
  }
}

/// D⁻¹ (row-major, full) from D's lower half, s × s: D = L P Lᵀ with L unit lower triangular
/// and P diagonal, so D⁻¹ = Mᵀ P⁻¹ M with M = L⁻¹. No square roots, one division per pivot.
/// False when a pivot is not positive (D not positive definite).
template <int S>
bool invertSpd(const double* d, double* out, int s_rt, double min_pivot) {
  constexpr int kMax = BlockLdlt::kMaxNodeSize;
  const int s = sizeOf<S>(s_rt);
  double l[kMax * kMax], p[kMax] = {}, inv_p[kMax] = {};
  COOPNAV_UNROLL
  for (int i = 0; i < s; ++i) {
    COOPNAV_UNROLL
    for (int j = 0; j < i; ++j) {
      double x = d[i * s + j];
      COOPNAV_UNROLL
      for (int k = 0; k < j; ++k) x -= l[i * s + k] * l[j * s + k] * p[k];
      l[i * s + j] = x * inv_p[j];
    }
    double pi = d[i * s + i];
    COOPNAV_UNROLL
    for (int k = 0; k < i; ++k) pi -= l[i * s + k] * l[i * s + k] * p[k];
    if (!(pi > min_pivot) || !std::isfinite(pi)) return false;
    p[i] = pi;
    inv_p[i] = 1.0 / pi;
  }
  double m[kMax * kMax];  // M = L⁻¹, unit lower
  COOPNAV_UNROLL
  for (int j = 0; j < s; ++j) {
    m[j * s + j] = 1.0;
    COOPNAV_UNROLL
    for (int i = j + 1; i < s; ++i) {
      double x = 0.0;
      COOPNAV_UNROLL
      for (int k = j; k < i; ++k) x -= l[i * s + k] * m[k * s + j];
      m[i * s + j] = x;
    }
  }
  COOPNAV_UNROLL
  for (int i = 0; i < s; ++i) {
    COOPNAV_UNROLL
    for (int j = 0; j <= i; ++j) {
      double x = 0.0;
      COOPNAV_UNROLL
      for (int k = i; k < s; ++k) x += m[k * s + i] * m[k * s + j] * inv_p[k];
      out[i * s + j] = out[j * s + i] = x;
    }
  }
  return true;
}

/// Calls f(SV, SU) with the sizes as std::integral_constant: fixed for the band problem's nodes
/// (4 = ΔT and pose, 1 = a lone ΔT), 0 (run time) for any other.
template <typename F>
inline void withSizes(int sv, int su, F&& f) {
  using K4 = std::integral_constant<int, 4>;
  using K1 = std::integral_constant<int, 1>;
  using K0 = std::integral_constant<int, 0>;
  if (sv == 4 && su == 4) {
    f(K4{}, K4{});
  } else if (sv == 4 && su == 1) {
    f(K4{}, K1{});
  } else if (sv == 1 && su == 4) {
    f(K1{}, K4{});
  } else if (sv == 1 && su == 1) {
    f(K1{}, K1{});
  } else {
    f(K0{}, K0{});
  }
}

/// w(c, r) = t(r, c), t: sv × su.
template <int SV, int SU>
inline void placeTransposed(const double* t, double* w, int sv_rt, int su_rt) {
  const int sv = sizeOf<SV>(sv_rt), su = sizeOf<SU>(su_rt);
  COOPNAV_UNROLL
  for (int r = 0; r < sv; ++r) {
    COOPNAV_UNROLL
    for (int c = 0; c < su; ++c) w[c * sv + r] = t[r * su + c];
  }
}

/// z = M z (M: s × s).
template <int S>
inline void multiplyInPlace(const double* m, double* z, int s_rt) {
  const int s = sizeOf<S>(s_rt);
  double t[BlockLdlt::kMaxNodeSize];
  COOPNAV_UNROLL
  for (int r = 0; r < s; ++r) {
    double x = 0.0;
    COOPNAV_UNROLL
    for (int c = 0; c < s; ++c) x += m[r * s + c] * z[c];
    t[r] = x;
  }
  std::copy(t, t + s, z);
}

/// zv −= L zu (L: sv × su).
template <int SV, int SU>
inline void subtractProduct(const double* l, const double* zu, double* zv, int sv_rt, int su_rt) {
  const int sv = sizeOf<SV>(sv_rt), su = sizeOf<SU>(su_rt);
  COOPNAV_UNROLL
  for (int r = 0; r < sv; ++r) {
    double x = 0.0;
    COOPNAV_UNROLL
    for (int c = 0; c < su; ++c) x += l[r * su + c] * zu[c];
    zv[r] -= x;
  }
}

/// zu −= Lᵀ zv (L: sv × su).
template <int SV, int SU>
inline void subtractTransposedProduct(const double* l, const double* zv, double* zu, int sv_rt,
                                      int su_rt) {
  const int sv = sizeOf<SV>(sv_rt), su = sizeOf<SU>(su_rt);
  COOPNAV_UNROLL
  for (int c = 0; c < su; ++c) {
    double x = 0.0;
    COOPNAV_UNROLL
    for (int r = 0; r < sv; ++r) x += l[r * su + c] * zv[r];
    zu[c] -= x;
  }
}

}  // namespace

bool BlockLdlt::invertDiagonal(int v, double* d) {
  const int s = size_[v];
  double* out = dvals_.data() + dinv_[v];
  switch (s) {
    case 1:
      return invertSpd<1>(d, out, s, kMinPivot);
    case 4:
      return invertSpd<4>(d, out, s, kMinPivot);
    default:
      return invertSpd<0>(d, out, s, kMinPivot);
  }
}

template <int SV, int SU>
void BlockLdlt::eliminate(int v, int u, int pos, double* d) {
  const int sv = sizeOf<SV>(size_[v]), su = sizeOf<SU>(size_[u]);
  // The workspace holds row v's tiles transposed, tile (v, x) at w + offset(x) · kMaxNodeSize
  // (a fixed place per node x, whatever v's size); so Yᵀ.
  double* w = work_.data();
  // Yᵀ = (L(v, u) D(u))ᵀ, taken out of the workspace (which is left zero).
  double yt[kMaxNodeSize * kMaxNodeSize];
  double* wu = w + offset_[u] * kMaxNodeSize;
  std::copy(wu, wu + su * sv, yt);
  std::fill(wu, wu + su * sv, 0.0);
  // L(v, u) = Y D(u)⁻¹, row r = Σ_k Y(r, k) D⁻¹(k, ·).
  double* __restrict l = lvals_.data() + entry_val_[pos];
  const double* __restrict di = dvals_.data() + dinv_[u];
  COOPNAV_UNROLL
  for (int r = 0; r < sv; ++r) {
    double row[kMaxNodeSize] = {};
    COOPNAV_UNROLL
    for (int k = 0; k < su; ++k) {
      const double f = yt[k * sv + r];
      COOPNAV_UNROLL
      for (int c = 0; c < su; ++c) row[c] += f * di[k * su + c];
    }
    std::copy(row, row + su, l + r * su);
  }
  // Y(v, x) −= Y L(x, u)ᵀ for the rows x of column u above v: all in v's pattern, right of u.
  for (int e = col_start_[u]; e < pos; ++e) {
    const int rx = entry_row_[e], sx = size_[rx];
    const double* lx = lvals_.data() + entry_val_[e];
    double* wx = w + offset_[rx] * kMaxNodeSize;
    if (sx == 4) {
      scatterUpdate<SV, SU, 4>(yt, lx, wx, sv, su, sx);
    } else if (sx == 1) {
      scatterUpdate<SV, SU, 1>(yt, lx, wx, sv, su, sx);
    } else {
      scatterUpdate<SV, SU, 0>(yt, lx, wx, sv, su, sx);
    }
  }
  // D(v) −= L(v, u) Y(v, u)ᵀ, whole (symmetric; invertDiagonal() reads the lower half).
  COOPNAV_UNROLL
  for (int i = 0; i < sv; ++i) {
    COOPNAV_UNROLL
    for (int k = 0; k < su; ++k) {
      const double f = l[i * su + k];
      COOPNAV_UNROLL
      for (int j = 0; j < sv; ++j) d[i * sv + j] -= f * yt[k * sv + j];
    }
  }
}

bool BlockLdlt::factorize(const double* a, double lambda) {
  for (int v = 0; v < n_; ++v) {
    if (!factorRow(v, a, lambda)) return false;
  }
  return true;
}

bool BlockLdlt::factorRow(int v, const double* a, double lambda) {
  double* w = work_.data();
  const int sv = size_[v];
  for (int q = nz_start_[v]; q < nz_start_[v + 1]; ++q) {
    const int k = nz_[q];
    const int u = lower_[k], su = size_[u];
    const double* t = a + tile_[k];
    double* wu = w + offset_[u] * kMaxNodeSize;
    withSizes(sv, su, [&](auto kv, auto ku) {
      placeTransposed<decltype(kv)::value, decltype(ku)::value>(t, wu, sv, su);
    });
  }
  double d[kMaxNodeSize * kMaxNodeSize];
  const double* av = a + diag_[v];
  for (int i = 0; i < sv; ++i) {
    for (int j = 0; j <= i; ++j) d[i * sv + j] = d[j * sv + i] = av[i * sv + j];
    d[i * sv + i] += lambda;
  }
  for (int k = row_start_[v]; k < row_start_[v + 1]; ++k) {
    const int u = pattern_[k], su = size_[u], pos = entry_pos_[k];
    withSizes(sv, su, [&](auto kv, auto ku) {
      eliminate<decltype(kv)::value, decltype(ku)::value>(v, u, pos, d);
    });
  }
  // Every pattern node took its workspace entries out: the workspace is zero again.
  return invertDiagonal(v, d);
}

void BlockLdlt::forwardRow(int v, double* z) const {
  const int sv = size_[v];
  double* zv = z + offset_[v];
  for (int k = row_start_[v]; k < row_start_[v + 1]; ++k) {
    const int u = pattern_[k], su = size_[u];
    const double* l = lvals_.data() + row_val_[k];
    withSizes(sv, su, [&](auto kv, auto ku) {
      subtractProduct<decltype(kv)::value, decltype(ku)::value>(l, z + offset_[u], zv, sv, su);
    });
  }
}

void BlockLdlt::scaleRow(int v, double* z) const {
  const int sv = size_[v];
  const double* di = dvals_.data() + dinv_[v];
  withSizes(sv, sv,
            [&](auto kv, auto) { multiplyInPlace<decltype(kv)::value>(di, z + offset_[v], sv); });
}

void BlockLdlt::backwardRow(int v, double* z) const {
  const int sv = size_[v];
  const double* zv = z + offset_[v];
  for (int k = row_start_[v]; k < row_start_[v + 1]; ++k) {
    const int u = pattern_[k], su = size_[u];
    const double* l = lvals_.data() + row_val_[k];
    withSizes(sv, su, [&](auto kv, auto ku) {
      subtractTransposedProduct<decltype(kv)::value, decltype(ku)::value>(l, zv, z + offset_[u], sv,
                                                                          su);
    });
  }
}

void BlockLdlt::solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const {
  *x = b;
  double* z = x->data();
  for (int v = 0; v < n_; ++v) forwardRow(v, z);
  for (int v = 0; v < n_; ++v) scaleRow(v, z);
  for (int v = n_ - 1; v >= 0; --v) backwardRow(v, z);
}

}  // namespace coopnav
