#include "coopnav/band/sparse_lm.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "coopnav/band/envelope_ldlt.hpp"

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
/// ~700 nodes, ~2.5 graphs a cycle).
struct Graph {
  std::vector<int> start;  ///< node v's neighbours: nbr[start[v] .. start[v + 1])
  std::vector<int> nbr;
  int size() const { return static_cast<int>(start.size()) - 1; }
  int degree(int v) const { return start[v + 1] - start[v]; }
  const int* begin(int v) const { return nbr.data() + start[v]; }
  const int* end(int v) const { return nbr.data() + start[v + 1]; }
};

/// Sloan's profile-reducing order ("An algorithm for profile and wavefront reduction of sparse
/// matrices", 1986; "A Fortran program for profile and wavefront reduction", 1989): numbered
/// from one end of a pseudo-diameter, each next node the one of highest priority
/// W1 · (levels from the far end) − W2 · (current degree + 1), with his W1 = 1, W2 = 2, the
/// current degree being the neighbours a node would still bring into the front. Where several
/// bands couple in time it follows the front better than reverse Cuthill–McKee's level order,
/// used until 2026-12-03 (bench_band, mean multiply-adds per factorisation: five humans 0.59
/// against 0.99 M, one human 0.070 against 0.101 M). Nodes are parameter blocks; weighting
/// them by their unknowns measured worse (0.68 M for five humans). The queue is the front, a
/// few dozen nodes: a linear scan for the maximum is cheaper than a heap whose keys change
/// every step. Deterministic (ties by index).
std::vector<int> sloanOrder(const Graph& adj) {
  constexpr long kW1 = 1, kW2 = 2;
  const int n = adj.size();
  std::vector<int> order, dist(n, -1), level;
  order.reserve(n);
  level.reserve(n);
  enum Status : char { kInactive, kPreactive, kActive, kNumbered };
  std::vector<Status> status(n, kInactive);
  // Breadth-first over the unnumbered nodes from s: dist, the visited nodes, and the last
  // level's node of least degree (the next pseudo-peripheral candidate).
  auto bfs = [&](int s) {
    for (int v : level) dist[v] = -1;
    level.assign(1, s);
    dist[s] = 0;
    for (std::size_t h = 0; h < level.size(); ++h) {
      for (const int* it = adj.begin(level[h]); it != adj.end(level[h]); ++it) {
        if (dist[*it] < 0 && status[*it] == kInactive) {
          dist[*it] = dist[level[h]] + 1;
          level.push_back(*it);
        }
      }
    }
    int far = level.back();
    for (int v : level) {
      if (dist[v] == dist[far] && adj.degree(v) < adj.degree(far)) far = v;
    }
    return far;
  };
  std::vector<long> priority(n, 0);
  std::vector<int> queue;
  for (int s0 = 0; s0 < n; ++s0) {
    if (status[s0] != kInactive) continue;
    bfs(s0);
    int start = s0;
    for (int v : level) {
      if (adj.degree(v) < adj.degree(start)) start = v;
    }
    const int end = bfs(bfs(start));
    start = level.front();
    bfs(end);  // dist: levels from the far end, over this component
    for (int v : level) priority[v] = kW1 * dist[v] - kW2 * (adj.degree(v) + 1);
    queue.assign(1, start);
    status[start] = kPreactive;
    auto enqueue = [&](int v) {
      if (status[v] == kInactive) {
        status[v] = kPreactive;
        queue.push_back(v);
      }
    };
    while (!queue.empty()) {
      std::size_t best = 0;
      for (std::size_t q = 1; q < queue.size(); ++q) {
        const int v = queue[q], b = queue[best];
        if (priority[v] > priority[b] || (priority[v] == priority[b] && v < b)) best = q;
      }
      const int i = queue[best];
      queue[best] = queue.back();
      queue.pop_back();
      if (status[i] == kPreactive) {
        for (const int* it = adj.begin(i); it != adj.end(i); ++it) {
          if (status[*it] == kNumbered) continue;
          priority[*it] += kW2;
          enqueue(*it);
        }
      }
      status[i] = kNumbered;
      order.push_back(i);
      for (const int* it = adj.begin(i); it != adj.end(i); ++it) {
        const int j = *it;
        if (status[j] != kPreactive) continue;
        status[j] = kActive;
        priority[j] += kW2;
        for (const int* kt = adj.begin(j); kt != adj.end(j); ++kt) {
          if (status[*kt] == kNumbered) continue;
          priority[*kt] += kW2;
          enqueue(*kt);
        }
      }
    }
  }
  return order;
}

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
    int offset;  ///< first unknown; -1 for a constant block
  };
  struct Block {
    const ceres::CostFunction* cost;
    std::size_t first_param;  ///< into block_params
    int num_params;
    int num_residuals;
    int jacobian_size;  ///< entries of its Jacobians w.r.t. the unknowns
  };

  std::vector<Param> params;
  PointerIndex param_index;
  std::vector<Block> blocks;
  std::vector<int> block_params;  ///< param indices of every block, flattened
  int num_unknowns{0};
  bool structure_ready{false};

  EnvelopeLdlt ldlt;
  std::vector<double> hessian;  ///< JᵀJ in ldlt's envelope storage (lower triangle)
  Eigen::VectorXd gradient;     ///< Jᵀr

  // Scratch reused by every evaluation (no allocation in the loop).
  std::vector<double> residuals;
  std::vector<double> jacobian_storage;
  std::vector<double*> jacobians;
  std::vector<const double*> param_ptrs;
  std::vector<double> columns;  ///< accumulateFixed(): up to kPad entries per Jacobian column
  /// Parameter blocks per residual block that accumulatePadded() handles on the stack.
  static constexpr int kMaxBlockParams = 16;

  /// Visits every upper-triangle JᵀJ entry a block contributes, in one fixed order:
  /// f(i, j, a, b, row, col): block parameter i's column a times parameter j's column b,
  /// row <= col, i.e. the envelope's lower entry (col, row).
  template <typename F>
  void forEachEntry(const Block& blk, F&& f) const {
    forEachPair(blk, [&](int i, int j, const Param& p, const Param& q) {
      for (int a = 0; a < p.size; ++a) {
        for (int b = i == j ? a : 0; b < q.size; ++b) f(i, j, a, b, p.offset + a, q.offset + b);
      }
    });
  }

  /// The pairs of unknown parameters whose JᵀJ sub-block forEachEntry() visits, in its order:
  /// f(i, j, p, q) with p.offset <= q.offset (i == j: the diagonal sub-block, upper half).
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

  /// Order of the unknown parameter blocks: Sloan's on the block graph, computed
  /// once per structure and applied to the offsets, so the normal equations are assembled in
  /// their factorisation order (no permutation per solve) with a small envelope.
  void assignOffsets() {
    std::vector<int> var_of(params.size(), -1), param_of;
    for (std::size_t k = 0; k < params.size(); ++k) {
      if (params[k].offset >= 0) {
        var_of[k] = static_cast<int>(param_of.size());
        param_of.push_back(static_cast<int>(k));
      }
    }
    // Edges of every block's pairs of unknowns, counted, placed, then deduplicated and sorted
    // per node: the same sorted neighbour lists as a set per node. A pair comes from every block
    // that holds both (consecutive poses share several), so repeats are dropped before sorting.
    const int nv = static_cast<int>(param_of.size());
    Graph adj;
    adj.start.assign(nv + 1, 0);
    auto forEachPair = [&](auto&& f) {
      for (const Block& blk : blocks) {
        for (int i = 0; i < blk.num_params; ++i) {
          const int vi = var_of[block_params[blk.first_param + i]];
          for (int j = 0; j < blk.num_params && vi >= 0; ++j) {
            const int vj = var_of[block_params[blk.first_param + j]];
            if (vj >= 0 && vi != vj) f(vi, vj);
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
    num_unknowns = 0;
    for (int v : sloanOrder(adj)) {
      Param& p = params[param_of[v]];
      p.offset = num_unknowns;
      num_unknowns += p.size;
    }
  }

  void buildStructure() {
    assignOffsets();
    std::vector<int> first(num_unknowns);
    for (int i = 0; i < num_unknowns; ++i) first[i] = i;
    std::size_t max_res = 1, max_jac = 1, max_params = 1, max_cols = 1;
    for (Block& blk : blocks) {
      // forEachEntry()'s entries (row <= col) are lower entries (col, row); the topmost row of
      // every column of q in the pair (p, q) is p's first row, so the envelope needs only that.
      blk.jacobian_size = 0;
      std::size_t jac = 0, cols = 0;
      for (int i = 0; i < blk.num_params; ++i) {
        const Param& p = params[block_params[blk.first_param + i]];
        jac += blk.num_residuals * p.size;
        cols += p.size;
        if (p.offset >= 0) blk.jacobian_size += blk.num_residuals * p.size;
      }
      forEachPair(blk, [&](int, int, const Param& p, const Param& q) {
        for (int b = 0; b < q.size; ++b) {
          first[q.offset + b] = std::min(first[q.offset + b], p.offset);
        }
      });
      max_res = std::max<std::size_t>(max_res, blk.num_residuals);
      max_jac = std::max(max_jac, jac);
      max_cols = std::max(max_cols, cols);
      max_params = std::max<std::size_t>(max_params, blk.num_params);
    }
    ldlt.setPattern(std::move(first));
    hessian.assign(ldlt.storage(), 0.0);
    gradient.resize(num_unknowns);
    residuals.resize(max_res);
    jacobian_storage.resize(max_jac);
    jacobians.resize(max_params);
    param_ptrs.resize(max_params);
    columns.assign(kPad * max_cols, 0.0);
    structure_ready = true;
  }

  double evaluateBlock(const Block& blk, bool with_jacobians) {
    double* jac = jacobian_storage.data();
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      param_ptrs[i] = p.values;
      if (with_jacobians && p.offset >= 0) {
        jacobians[i] = jac;
        jac += blk.num_residuals * p.size;
      } else {
        jacobians[i] = nullptr;
      }
    }
    if (!blk.cost->Evaluate(param_ptrs.data(), residuals.data(),
                            with_jacobians ? jacobians.data() : nullptr)) {
      return std::numeric_limits<double>::infinity();
    }
    double c = 0.0;
    for (int k = 0; k < blk.num_residuals; ++k) c += residuals[k] * residuals[k];
    return 0.5 * c;
  }

  /// ½ Σ r² over the blocks, in their order. Stops once the sum reaches `stop_at`: every block's
  /// cost is non-negative, so the full sum could only be larger.
  double cost(double stop_at = std::numeric_limits<double>::infinity()) {
    double c = 0.0;
    for (const Block& blk : blocks) {
      c += evaluateBlock(blk, false);
      if (c >= stop_at) break;
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
    std::copy(residuals.begin(), residuals.begin() + kM, r);
    // Columns of the unknown parameters, in block order: column (i, a) at col_base[i] + a.
    double* cols = columns.data();
    int col_base[kMaxBlockParams];
    int ncols = 0;
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      col_base[i] = ncols;
      if (p.offset < 0) continue;
      const double* J = jacobians[i];  // row-major kM × size
      for (int a = 0; a < p.size; ++a, ++ncols) {
        double* c = cols + kM * ncols;
        for (int k = 0; k < kM; ++k) c[k] = J[k * p.size + a];
        gradient[p.offset + a] += dotFixed<kM>(c, r);
      }
    }
    // Each entry's place comes from the envelope's row bases (a few KB) rather than from a list
    // of places per entry (for five humans ~300 KB, read every assembly).
    double* h = hessian.data();
    forEachEntry(blk, [&](int i, int j, int a, int b, int row, int col) {
      h[ldlt.slot(col, row)] +=
          dotFixed<kM>(cols + kM * (col_base[i] + a), cols + kM * (col_base[j] + b));
    });
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
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      if (p.offset < 0) continue;
      const double* J = jacobians[i];  // row-major m × size
      for (int a = 0; a < p.size; ++a) {
        double s = 0.0;
        for (int k = 0; k < m; ++k) s += J[k * p.size + a] * residuals[k];
        gradient[p.offset + a] += s;
      }
    }
    double* h = hessian.data();
    forEachEntry(blk, [&](int i, int j, int a, int b, int row, int col) {
      const int pi = params[block_params[blk.first_param + i]].size;
      const int pj = params[block_params[blk.first_param + j]].size;
      double sum = 0.0;
      for (int k = 0; k < m; ++k) sum += jacobians[i][k * pi + a] * jacobians[j][k * pj + b];
      h[ldlt.slot(col, row)] += sum;
    });
  }

  /// Cost, Jᵀr and JᵀJ at the current parameters (JᵀJ's rows narrowed to its non-zeros).
  double linearize() {
    ldlt.clear(hessian.data());
    gradient.setZero();
    double c = 0.0;
    for (const Block& blk : blocks) {
      c += evaluateBlock(blk, true);
      // An inactive penalty (a hinge inside its allowed set) has an exactly zero Jacobian and
      // adds nothing: most blocks of a band are such at any time (no limit violated, no wall or
      // agent near).
      const double* jac = jacobian_storage.data();
      if (std::all_of(jac, jac + blk.jacobian_size, [](double v) { return v == 0.0; })) {
        continue;
      }
      if (!accumulatePadded(blk)) accumulateGeneral(blk);
    }
    ldlt.narrowTo(hessian.data());
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
  if (impl_->param_index.find(values) >= 0) throw std::logic_error("parameter block added twice");
  impl_->param_index.insert(values, static_cast<int>(impl_->params.size()));
  impl_->params.push_back({values, size, constant ? -1 : 0});
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
  Impl::Block blk{cost, impl_->block_params.size(), num_params, cost->num_residuals(), 0};
  for (int i = 0; i < num_params; ++i) {
    const int k = impl_->param_index.find(params[i]);
    if (k < 0 || impl_->params[k].size != sizes[i]) {
      throw std::logic_error("residual block: undeclared or mis-sized parameter block");
    }
    impl_->block_params.push_back(k);
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
    for (int i = 0; i < m.num_unknowns; ++i)
      max_diagonal = std::max(max_diagonal, m.hessian[m.ldlt.slot(i, i)]);
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
    // dot products instead of a product with the envelope.
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
