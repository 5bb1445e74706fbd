#include "coopnav/band/sparse_lm.hpp"

#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "coopnav/band/block_ldlt.hpp"

namespace coopnav {
namespace {

/// Ceres' defaults, kept so that both solvers take the same steps on the same problem: the first
/// damping equals Ceres' 1 / initial_trust_region_radius with a unit LM diagonal, and a step counts
/// as successful above Ceres' min_relative_decrease.
constexpr double kInitialLambda = 1.0;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kMinLambda = 1e-16;
constexpr double kMaxLambda = 1e32;

/// An undirected graph as compressed adjacency lists (one array each, not a vector per node:
/// ~400 nodes, ~2.5 graphs a cycle).
struct Graph {
  std::vector<int> start;  ///< node v's neighbours: nbr[start[v] .. start[v + 1])
  std::vector<int> nbr;
  const int* begin(int v) const { return nbr.data() + start[v]; }
  const int* end(int v) const { return nbr.data() + start[v + 1]; }
};

/// Index of each parameter block by its address: open addressing with linear probing, so that
/// declaring the ~700 blocks of a band problem (rebuilt ~2.5 times a cycle) allocates a few
/// arrays, not a node per block as std::unordered_map does.
class PointerIndex {
 public:
  /// -1 when absent.
  int find(const double* key) const {
    if (keys_.empty()) return -1;
    for (std::size_t h = slotOf(key);; h = (h + 1) & mask_) {
      if (keys_[h] == key) return values_[h];
      if (keys_[h] == nullptr) return -1;
    }
  }
  /// key must be non-null and absent.
  void insert(const double* key, int value) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    std::size_t h = slotOf(key);
    while (keys_[h] != nullptr) h = (h + 1) & mask_;
    keys_[h] = key;
    values_[h] = value;
    ++size_;
  }

 private:
  std::size_t slotOf(const double* key) const {
    // Fibonacci hashing of the address (doubles: the low 3 bits are zero).
    const auto x = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(key) >> 3);
    return static_cast<std::size_t>((x * 0x9E3779B97F4A7C15ull) >> 32) & mask_;
  }
  void grow() {
    std::vector<const double*> old_keys = std::move(keys_);
    std::vector<int> old_values = std::move(values_);
    const std::size_t cap = std::max<std::size_t>(64, 2 * old_keys.size());
    keys_.assign(cap, nullptr);
    values_.assign(cap, -1);
    mask_ = cap - 1;
    size_ = 0;
    for (std::size_t k = 0; k < old_keys.size(); ++k) {
      if (old_keys[k] != nullptr) insert(old_keys[k], old_values[k]);
    }
  }
  std::vector<const double*> keys_;
  std::vector<int> values_;
  std::size_t mask_{0};
  std::size_t size_{0};
};

}  // namespace

struct SparseLm::Impl {
  struct Param {
    double* values;
    int size;
    int offset;   ///< first unknown; -1 for a constant block
    int node;     ///< node of the factorisation (elimination order); -1 for a constant block
    int in_node;  ///< its first unknown's place in the node
  };
  /// Unknowns per node at most (BlockLdlt's kernels are fixed for 4 and 1).
  static constexpr int kNodeSize = 4;
  static_assert(kNodeSize <= BlockLdlt::kMaxNodeSize);
  struct Block {
    const ceres::CostFunction* cost;
    std::size_t first_param;  ///< into block_params
    int num_params;
    int num_residuals;
    int jacobian_size;  ///< entries of its Jacobians w.r.t. the unknowns
    int first_tile;     ///< into pair_tiles: its JᵀJ tiles (2 ints each) in forEachPair() order
  };

  std::vector<Param> params;
  PointerIndex param_index;
  std::vector<Block> blocks;
  std::vector<int> block_params;      ///< param indices of every block, flattened
  std::vector<double*> block_values;  ///< their values, flattened alike (Evaluate()'s argument)
  int num_unknowns{0};
  bool structure_ready{false};

  BlockLdlt ldlt;
  std::vector<double> hessian;  ///< JᵀJ in ldlt's tiles (lower triangle)
  /// Per block, for each JᵀJ tile it adds to: the storage offset of its first entry and the
  /// tile's row stride.
  std::vector<int> pair_tiles;
  Eigen::VectorXd gradient;  ///< Jᵀr

  /// Scratch reused by every evaluation (no allocation in the loop).
  struct Scratch {
    std::vector<double> residuals;
    std::vector<double> jacobian_storage;
    std::vector<double*> jacobians;
    std::vector<double> columns;  ///< accumulateFixed(): up to kPad entries per Jacobian column
  };
  Scratch scratch;
  /// Parameter blocks per residual block that accumulatePadded() handles on the stack.
  static constexpr int kMaxBlockParams = 16;

  /// Visits every JᵀJ entry a block contributes, in one fixed order: f(i, j, a, b, entry):
  /// block parameter i's column a times parameter j's column b, at `entry` of the lower tile
  /// (q's row b, p's column a) of forEachPair()'s pair (p, q).
  template <typename F>
  void forEachEntry(const Block& blk, F&& f) {
    forEachTile(blk, [&](int i, int j, const Param& p, const Param& q, double* t, int stride) {
      for (int a = 0; a < p.size; ++a) {
        for (int b = i == j ? a : 0; b < q.size; ++b) f(i, j, a, b, t + b * stride + a);
      }
    });
  }

  /// forEachPair() with each pair's JᵀJ tile: f(i, j, p, q, t, stride), entry (q's b, p's a) at
  /// t[b · stride + a] (pair_tiles, laid out by buildStructure()).
  template <typename F>
  void forEachTile(const Block& blk, F&& f) {
    const int* tiles = pair_tiles.data() + blk.first_tile;
    double* h = hessian.data();
    forEachPair(blk, [&](int i, int j, const Param& p, const Param& q) {
      f(i, j, p, q, h + tiles[0], tiles[1]);
      tiles += 2;
    });
  }

  /// The pairs of unknown parameters whose JᵀJ tile forEachEntry() visits, in its order:
  /// f(i, j, p, q) with p.offset <= q.offset (i == j: the diagonal tile, lower half).
  template <typename F>
  void forEachPair(const Block& blk, F&& f) const {
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      if (p.offset < 0) continue;
      for (int j = 0; j < blk.num_params; ++j) {
        const Param& q = params[block_params[blk.first_param + j]];
        if (q.offset < 0 || (i != j && p.offset > q.offset)) continue;
        f(i, j, p, q);
      }
    }
  }

  /// Nodes of the unknowns and their elimination order, computed once per structure and
  /// applied to the offsets, so the normal equations are assembled in their factorisation order
  /// (no permutation per solve).
  void assignOffsets() {
    std::vector<int> var_of(params.size(), -1), param_of;
    for (std::size_t k = 0; k < params.size(); ++k) {
      if (params[k].offset >= 0) {
        var_of[k] = static_cast<int>(param_of.size());
        param_of.push_back(static_cast<int>(k));
      }
    }
    // Nodes: unknowns declared one after the other that share a residual block, up to
    // kNodeSize unknowns (a band declares pose i, then ΔT_i: nodes {ΔT_i−1, pose i}). The
    // factorisation's work per tile costs about the same for 1 or 16 products, and a band's
    // ΔT is tied to the poses around it anyway.
    const int nvar = static_cast<int>(param_of.size());
    std::vector<char> linked(nvar, 0);  // var v and v + 1 share a block
    for (const Block& blk : blocks) {
      for (int i = 0; i < blk.num_params; ++i) {
        const int vi = var_of[block_params[blk.first_param + i]];
        for (int j = 0; j < blk.num_params && vi >= 0; ++j) {
          if (var_of[block_params[blk.first_param + j]] == vi + 1) linked[vi] = 1;
        }
      }
    }
    std::vector<int> group_of(nvar), group_first, group_size;
    for (int v = 0; v < nvar; ++v) {
      const int size = params[param_of[v]].size;
      if (v > 0 && linked[v - 1] && group_size.back() + size <= kNodeSize) {
        group_size.back() += size;
      } else {
        group_first.push_back(v);
        group_size.push_back(size);
      }
      group_of[v] = static_cast<int>(group_first.size()) - 1;
    }
    group_first.push_back(nvar);
    // Each block's distinct nodes (a band term's 1-6 parameter blocks fall in 1-4 nodes), then
    // the edges between them, counted, placed, deduplicated and sorted per node: the same sorted
    // neighbour lists as a set per node. A pair comes from every block that holds both
    // (consecutive poses share several), so repeats are dropped before sorting.
    const int nv = static_cast<int>(group_size.size());
    std::vector<int> block_nodes, block_start(blocks.size() + 1, 0);
    block_nodes.reserve(block_params.size());
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const Block& blk = blocks[b];
      const auto first = static_cast<std::ptrdiff_t>(block_nodes.size());
      for (int i = 0; i < blk.num_params; ++i) {
        const int pv = var_of[block_params[blk.first_param + i]];
        if (pv < 0) continue;
        const int g = group_of[pv];
        if (std::find(block_nodes.begin() + first, block_nodes.end(), g) == block_nodes.end())
          block_nodes.push_back(g);
      }
      block_start[b + 1] = static_cast<int>(block_nodes.size());
    }
    Graph adj;
    adj.start.assign(nv + 1, 0);
    auto forEachPair = [&](auto&& f) {
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        for (int i = block_start[b]; i < block_start[b + 1]; ++i) {
          for (int j = block_start[b]; j < block_start[b + 1]; ++j) {
            if (i != j) f(block_nodes[i], block_nodes[j]);
          }
        }
      }
    };
    forEachPair([&](int vi, int) { ++adj.start[vi + 1]; });
    for (int v = 0; v < nv; ++v) adj.start[v + 1] += adj.start[v];
    adj.nbr.resize(adj.start[nv]);
    std::vector<int> fill(adj.start.begin(), adj.start.end() - 1);
    forEachPair([&](int vi, int vj) { adj.nbr[fill[vi]++] = vj; });
    int out = 0;
    std::vector<int> seen_by(nv, -1);  // the last node whose list held it
    for (int v = 0; v < nv; ++v) {
      const int first = out;
      for (int k = adj.start[v]; k < adj.start[v + 1]; ++k) {
        const int u = adj.nbr[k];
        if (seen_by[u] == v) continue;
        seen_by[u] = v;
        adj.nbr[out++] = u;
      }
      std::sort(adj.nbr.data() + first, adj.nbr.data() + out);
      adj.start[v] = first;
    }
    adj.start[nv] = out;
    adj.nbr.resize(out);
    // Minimum degree (Eigen's AMD: Amestoy, Davis & Duff 1996) on the block graph, given as the
    // lower triangle of its pattern. It must hold the diagonal: Eigen's AMD takes a node
    // without one for a dense node and leaves it, in order, to the end (all of them: the
    // identity).
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> pattern(nv, nv);
    pattern.resizeNonZeros(static_cast<Eigen::Index>(adj.nbr.size() / 2) + nv);
    {
      int* outer = pattern.outerIndexPtr();
      int* inner = pattern.innerIndexPtr();
      int q = 0;
      for (int v = 0; v < nv; ++v) {
        outer[v] = q;
        inner[q++] = v;
        for (const int* it = adj.begin(v); it != adj.end(v); ++it) {
          if (*it > v) inner[q++] = *it;
        }
      }
      outer[nv] = q;
      std::fill(pattern.valuePtr(), pattern.valuePtr() + q, 1.0);
    }
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
    Eigen::AMDOrdering<int>()(pattern.selfadjointView<Eigen::Lower>(), perm);
    std::vector<int> node_of(nv), sizes(nv);
    num_unknowns = 0;
    for (int k = 0; k < nv; ++k) {
      const int v = perm.indices()[k];
      node_of[v] = k;
      sizes[k] = group_size[v];
      for (int g = group_first[v], in = 0; g < group_first[v + 1]; ++g) {
        Param& p = params[param_of[g]];
        p.offset = num_unknowns;
        p.node = k;
        p.in_node = in;
        in += p.size;
        num_unknowns += p.size;
      }
    }
    // Each node's neighbours eliminated before it, ascending.
    std::vector<int> start(nv + 1, 0), lower;
    lower.reserve(adj.nbr.size() / 2);
    for (int k = 0; k < nv; ++k) {
      const int v = perm.indices()[k];
      const std::size_t first = lower.size();
      for (const int* it = adj.begin(v); it != adj.end(v); ++it) {
        if (node_of[*it] < k) lower.push_back(node_of[*it]);
      }
      std::sort(lower.begin() + first, lower.end());
      start[k + 1] = static_cast<int>(lower.size());
    }
    ldlt.setStructure(std::move(sizes), std::move(start), std::move(lower));
  }

  void buildStructure() {
    assignOffsets();
    pair_tiles.clear();
    std::size_t max_res = 1, max_jac = 1, max_params = 1, max_cols = 1;
    for (Block& blk : blocks) {
      blk.jacobian_size = 0;
      std::size_t jac = 0, cols = 0;
      for (int i = 0; i < blk.num_params; ++i) {
        const Param& p = params[block_params[blk.first_param + i]];
        jac += blk.num_residuals * p.size;
        cols += p.size;
        if (p.offset >= 0) blk.jacobian_size += blk.num_residuals * p.size;
      }
      blk.first_tile = static_cast<int>(pair_tiles.size());
      // Entry (q's b, p's a) of the pair's tile: at base + b · stride + a.
      forEachPair(blk, [&](int, int, const Param& p, const Param& q) {
        const int tile = p.node == q.node ? ldlt.diagonalTile(p.node) : ldlt.tile(q.node, p.node);
        const int stride = ldlt.nodeSize(p.node);
        pair_tiles.push_back(tile + q.in_node * stride + p.in_node);
        pair_tiles.push_back(stride);
      });
      max_res = std::max<std::size_t>(max_res, blk.num_residuals);
      max_jac = std::max(max_jac, jac);
      max_cols = std::max(max_cols, cols);
      max_params = std::max<std::size_t>(max_params, blk.num_params);
    }
    hessian.assign(ldlt.storage(), 0.0);
    gradient.resize(num_unknowns);
    scratch.residuals.resize(max_res);
    scratch.jacobian_storage.resize(max_jac);
    scratch.jacobians.resize(max_params);
    scratch.columns.assign(kPad * max_cols, 0.0);
    structure_ready = true;
  }

  double evaluateBlock(const Block& blk, bool with_jacobians) {
    if (with_jacobians) {
      double* jac = scratch.jacobian_storage.data();
      for (int i = 0; i < blk.num_params; ++i) {
        const Param& p = params[block_params[blk.first_param + i]];
        if (p.offset >= 0) {
          scratch.jacobians[i] = jac;
          jac += blk.num_residuals * p.size;
        } else {
          scratch.jacobians[i] = nullptr;
        }
      }
    }
    if (!blk.cost->Evaluate(block_values.data() + blk.first_param, scratch.residuals.data(),
                            with_jacobians ? scratch.jacobians.data() : nullptr)) {
      return std::numeric_limits<double>::infinity();
    }
    double c = 0.0;
    for (int k = 0; k < blk.num_residuals; ++k) c += scratch.residuals[k] * scratch.residuals[k];
    return 0.5 * c;
  }

  /// ½ Σ r² over the blocks, summed in block order. Once it is known to reach `stop_at` it
  /// returns +inf (every block's cost is non-negative, so the full sum could only be larger).
  double cost(double stop_at = std::numeric_limits<double>::infinity()) {
    double c = 0.0;
    for (const Block& blk : blocks) {
      c += evaluateBlock(blk, false);
      if (c >= stop_at) return std::numeric_limits<double>::infinity();
    }
    return c;
  }

  /// Residual count up to which a block's Jacobian is transposed into columns of kM <= kPad
  /// entries: every JᵀJ entry is then kM products with no loop over the residuals (all band
  /// terms have 1-4 residuals).
  static constexpr int kPad = 4;

  /// Σ_k x[k] y[k], left to right.
  template <int kM>
  static double dotFixed(const double* x, const double* y) {
    double s = x[0] * y[0];
    for (int k = 1; k < kM; ++k) s += x[k] * y[k];
    return s;
  }

  /// Adds a block's Jᵀr and JᵀJ (block evaluated into the scratch, kM residuals). The sums are
  /// those of four products padded with zeros, to the bit (a padded +0.0 changes no sum that
  /// starts from +0.0, as the gradient and the Hessian do).
  template <int kM>
  void accumulateFixed(const Block& blk) {
    double r[kM];
    std::copy(scratch.residuals.begin(), scratch.residuals.begin() + kM, r);
    // Columns of the unknown parameters, in block order: column (i, a) at col_base[i] + a.
    double* cols = scratch.columns.data();
    int col_base[kMaxBlockParams];
    int ncols = 0;
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      col_base[i] = ncols;
      if (p.offset < 0) continue;
      const double* J = scratch.jacobians[i];  // row-major kM × size
      for (int a = 0; a < p.size; ++a, ++ncols) {
        double* c = cols + kM * ncols;
        for (int k = 0; k < kM; ++k) c[k] = J[k * p.size + a];
        gradient[p.offset + a] += dotFixed<kM>(c, r);
      }
    }
    // forEachEntry()'s entries and sums, with the tile's loops fixed at the band's parameter
    // sizes (3 and 1) so that they unroll.
    forEachTile(blk, [&](int i, int j, const Param& p, const Param& q, double* t, int stride) {
      const double* ci = cols + kM * col_base[i];
      const double* cj = cols + kM * col_base[j];
      if (i == j) {
        if (p.size == 3) return addTile<kM, 3, 3, true>(ci, cj, t, stride, 3, 3);
        if (p.size == 1) return addTile<kM, 1, 1, true>(ci, cj, t, stride, 1, 1);
        return addTile<kM, 0, 0, true>(ci, cj, t, stride, p.size, q.size);
      }
      if (p.size == 3 && q.size == 3) return addTile<kM, 3, 3, false>(ci, cj, t, stride, 3, 3);
      if (p.size == 3 && q.size == 1) return addTile<kM, 3, 1, false>(ci, cj, t, stride, 3, 1);
      if (p.size == 1 && q.size == 3) return addTile<kM, 1, 3, false>(ci, cj, t, stride, 1, 3);
      if (p.size == 1 && q.size == 1) return addTile<kM, 1, 1, false>(ci, cj, t, stride, 1, 1);
      return addTile<kM, 0, 0, false>(ci, cj, t, stride, p.size, q.size);
    });
  }

  /// t[b · stride + a] += column a of p · column b of q (kM entries each), over b >= a on the
  /// diagonal tile: forEachEntry()'s entries in its order. kP, kQ: the sizes if fixed, else 0.
  template <int kM, int kP, int kQ, bool kDiagonal>
  static void addTile(const double* cp, const double* cq, double* t, int stride, int p_size,
                      int q_size) {
    const int np = kP > 0 ? kP : p_size, nq = kQ > 0 ? kQ : q_size;
#pragma GCC unroll 3
    for (int a = 0; a < np; ++a) {
#pragma GCC unroll 3
      for (int b = kDiagonal ? a : 0; b < nq; ++b) {
        t[b * stride + a] += dotFixed<kM>(cp + kM * a, cq + kM * b);
      }
    }
  }

  /// accumulateFixed<m>() for the block's residual count m in 1..kPad; false otherwise.
  bool accumulatePadded(const Block& blk) {
    if (blk.num_params > kMaxBlockParams) return false;
    switch (blk.num_residuals) {
      case 1:
        accumulateFixed<1>(blk);
        return true;
      case 2:
        accumulateFixed<2>(blk);
        return true;
      case 3:
        accumulateFixed<3>(blk);
        return true;
      case 4:
        accumulateFixed<4>(blk);
        return true;
      default:
        return false;
    }
  }

  /// As accumulatePadded() for any residual count.
  void accumulateGeneral(const Block& blk) {
    const int m = blk.num_residuals;
    const std::vector<double*>& jacobians = scratch.jacobians;
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      if (p.offset < 0) continue;
      const double* J = jacobians[i];  // row-major m × size
      for (int a = 0; a < p.size; ++a) {
        double s = 0.0;
        for (int k = 0; k < m; ++k) s += J[k * p.size + a] * scratch.residuals[k];
        gradient[p.offset + a] += s;
      }
    }
    forEachEntry(blk, [&](int i, int j, int a, int b, double* entry) {
      const int pi = params[block_params[blk.first_param + i]].size;
      const int pj = params[block_params[blk.first_param + j]].size;
      double sum = 0.0;
      for (int k = 0; k < m; ++k) sum += jacobians[i][k * pi + a] * jacobians[j][k * pj + b];
      *entry += sum;
    });
  }

  /// A block's cost (returned), Jᵀr and JᵀJ.
  double linearizeBlock(const Block& blk) {
    const double c = evaluateBlock(blk, true);
    // An inactive penalty (a hinge inside its allowed set) has an exactly zero Jacobian and
    // adds nothing: most blocks of a band are such at any time (no limit violated, no wall or
    // agent near).
    const double* jac = scratch.jacobian_storage.data();
    if (std::all_of(jac, jac + blk.jacobian_size, [](double v) { return v == 0.0; })) return c;
    if (!accumulatePadded(blk)) accumulateGeneral(blk);
    return c;
  }

  /// Cost, Jᵀr and JᵀJ at the current parameters (and the pattern of JᵀJ's non-zero tiles).
  double linearize() {
    ldlt.clear(hessian.data());
    gradient.setZero();
    double c = 0.0;
    for (const Block& blk : blocks) c += linearizeBlock(blk);
    ldlt.analyze(hessian.data());
    return c;
  }

  void saveUnknowns(Eigen::VectorXd* x) const {
    x->resize(num_unknowns);
    for (const Param& p : params) {
      if (p.offset < 0) continue;
      for (int a = 0; a < p.size; ++a) (*x)[p.offset + a] = p.values[a];
    }
  }
  void setUnknowns(const Eigen::VectorXd& x) {
    for (const Param& p : params) {
      if (p.offset < 0) continue;
      for (int a = 0; a < p.size; ++a) p.values[a] = x[p.offset + a];
    }
  }
};

SparseLm::SparseLm() : impl_(std::make_unique<Impl>()) {}
SparseLm::~SparseLm() = default;

void SparseLm::addParameterBlock(double* values, int size, bool constant) {
  if (values == nullptr) throw std::logic_error("parameter block without storage");
  if (size < 1 || size > BlockLdlt::kMaxNodeSize)
    throw std::logic_error("parameter block size out of 1.." +
                           std::to_string(BlockLdlt::kMaxNodeSize));
  if (impl_->param_index.find(values) >= 0) throw std::logic_error("parameter block added twice");
  impl_->param_index.insert(values, static_cast<int>(impl_->params.size()));
  impl_->params.push_back({values, size, constant ? -1 : 0, -1, 0});
  impl_->structure_ready = false;
}

std::size_t SparseLm::addResidualBlock(const ceres::CostFunction* cost,
                                       const std::vector<double*>& params) {
  return addResidualBlock(cost, params.data(), static_cast<int>(params.size()));
}

std::size_t SparseLm::addResidualBlock(const ceres::CostFunction* cost, double* const* params,
                                       int num_params) {
  const auto& sizes = cost->parameter_block_sizes();
  if (num_params < 0 || sizes.size() != static_cast<std::size_t>(num_params))
    throw std::logic_error("residual block: parameter count");
  Impl::Block blk{cost, impl_->block_params.size(), num_params, cost->num_residuals(), 0, 0};
  for (int i = 0; i < num_params; ++i) {
    const int k = impl_->param_index.find(params[i]);
    if (k < 0 || impl_->params[k].size != sizes[i]) {
      throw std::logic_error("residual block: undeclared or mis-sized parameter block");
    }
    // One JᵀJ tile per pair of distinct blocks (Ceres refuses repeats too).
    if (std::find(params, params + i, params[i]) != params + i)
      throw std::logic_error("residual block: a parameter block named twice");
    impl_->block_params.push_back(k);
    impl_->block_values.push_back(impl_->params[k].values);
  }
  impl_->blocks.push_back(blk);
  impl_->structure_ready = false;
  return impl_->blocks.size() - 1;
}

double SparseLm::blockCost(std::size_t block) {
  if (!impl_->structure_ready) impl_->buildStructure();
  return impl_->evaluateBlock(impl_->blocks[block], false);
}

std::size_t SparseLm::numUnknowns() {
  if (!impl_->structure_ready) impl_->buildStructure();
  return static_cast<std::size_t>(impl_->num_unknowns);
}
std::size_t SparseLm::numResidualBlocks() const { return impl_->blocks.size(); }

SparseLm::Summary SparseLm::solve(const Options& options) {
  Impl& m = *impl_;
  if (!m.structure_ready) m.buildStructure();
  Summary s;
  double cost = m.linearize();
  s.initial_cost = s.final_cost = cost;
  if (m.num_unknowns == 0 || !std::isfinite(cost)) return s;
  double lambda = kInitialLambda;
  if (options.initial_lambda > 0.0) {
    lambda = options.initial_lambda;
  } else if (options.initial_lambda_scale > 0.0) {
    double max_diagonal = 0.0;
    for (const Impl::Param& p : m.params) {
      for (int a = 0; p.offset >= 0 && a < p.size; ++a) {
        max_diagonal =
            std::max(max_diagonal, m.hessian[m.ldlt.diagonalTile(p.node) +
                                             (p.in_node + a) * (m.ldlt.nodeSize(p.node) + 1)]);
      }
    }
    if (max_diagonal > 0.0 && std::isfinite(max_diagonal))
      lambda = options.initial_lambda_scale * max_diagonal;
  }
  lambda = std::clamp(lambda, kMinLambda, kMaxLambda);
  s.initial_lambda = lambda;
  double nu = 2.0;
  Eigen::VectorXd x_old, delta;
  while (s.iterations < options.max_iterations) {
    if (options.should_stop && options.should_stop()) {
      s.stopped = true;
      break;
    }
    if (m.gradient.lpNorm<Eigen::Infinity>() < options.gradient_tolerance) break;
    const bool factorized = m.ldlt.factorize(m.hessian.data(), lambda);
    ++s.iterations;
    if (!factorized) {
      lambda = std::min(lambda * nu, kMaxLambda);
      nu *= 2.0;
      continue;
    }
    m.ldlt.solve(-m.gradient, &delta);
    m.saveUnknowns(&x_old);
    if (delta.norm() < options.parameter_tolerance * (x_old.norm() + options.parameter_tolerance))
      break;
    // Predicted decrease of the linear model, −(gᵀδ + ½ δᵀHδ), which for the damped step
    // (H + λI)δ = −g equals ½ (λ δᵀδ − gᵀδ) (Madsen, Nielsen & Tingleff 2004, §3.2): two
    // dot products instead of a product with JᵀJ.
    const double model = 0.5 * (lambda * delta.squaredNorm() - m.gradient.dot(delta));
    m.setUnknowns(x_old + delta);
    // A step the model does not expect to lower the cost is rejected unevaluated, and one that
    // reaches the current cost before all its blocks are summed is rejected there (about half
    // the steps are rejected): the same decisions and iterates as with the full sum.
    const double new_cost = model > 0.0 ? m.cost(cost) : std::numeric_limits<double>::infinity();
    const double rho = model > 0.0 ? (cost - new_cost) / model : -1.0;
    if (std::isfinite(new_cost) && rho > kMinRelativeDecrease) {
      ++s.accepted;
      const double t = 2.0 * rho - 1.0;
      lambda = std::max(lambda * std::max(1.0 / 3.0, 1.0 - t * t * t), kMinLambda);
      nu = 2.0;
      const double decrease = (cost - new_cost) / cost;
      cost = new_cost;
      if (decrease < options.function_tolerance) break;
      // After the last step nothing would read the Jacobians (the cost is the one just summed,
      // in the same block order): a band solve ends on an accepted step in most outer iterations.
      if (s.iterations >= options.max_iterations) break;
      cost = m.linearize();
    } else {
      m.setUnknowns(x_old);
      lambda = std::min(lambda * nu, kMaxLambda);
      nu *= 2.0;
    }
  }
  s.final_cost = cost;
  s.final_lambda = lambda;
  return s;
}

}  // namespace coopnav
