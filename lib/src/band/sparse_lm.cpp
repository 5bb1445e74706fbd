#include "coopnav/band/sparse_lm.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace coopnav {
namespace {

/// Ceres' defaults, kept so that both solvers take the same steps on the same problem: the first
/// damping equals Ceres' 1 / initial_trust_region_radius with a unit LM diagonal, and a step counts
/// as successful above Ceres' min_relative_decrease.
constexpr double kInitialLambda = 1.0;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kMinLambda = 1e-16;
constexpr double kMaxLambda = 1e32;

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
    std::size_t first_slot;  ///< into slots (JᵀJ destinations in accumulation order)
  };

  std::vector<Param> params;
  std::unordered_map<const double*, int> param_index;
  std::vector<Block> blocks;
  std::vector<int> block_params;  ///< param indices of every block, flattened
  int num_unknowns{0};
  bool structure_ready{false};

  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  Matrix hessian;             ///< JᵀJ, upper triangle, fixed pattern
  std::vector<int> slots;     ///< value index in `hessian` per JᵀJ entry, accumulation order
  std::vector<int> diagonal;  ///< value index of every H(i, i)
  Eigen::SimplicialLDLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt;
  Eigen::VectorXd gradient;  ///< Jᵀr
  double lambda{kInitialLambda};

  // Scratch reused by every evaluation (no allocation in the loop).
  std::vector<double> residuals;
  std::vector<double> jacobian_storage;
  std::vector<double*> jacobians;
  std::vector<const double*> param_ptrs;

  int slotOf(int row, int col) const {
    const int* inner = hessian.innerIndexPtr();
    const int* begin = inner + hessian.outerIndexPtr()[col];
    const int* end = inner + hessian.outerIndexPtr()[col + 1];
    const int* it = std::lower_bound(begin, end, row);
    return static_cast<int>(it - inner);
  }

  /// Visits every upper-triangle JᵀJ entry a block contributes, in one fixed order:
  /// f(i, j, a, b, row, col): block parameter i's column a times parameter j's column b,
  /// row <= col (Eigen's simplicial LDLᵀ reads the upper triangle in place without a copy when
  /// no ordering is asked of it; ours is applied to the offsets, see buildStructure()).
  template <typename F>
  void forEachEntry(const Block& blk, F&& f) const {
    for (int i = 0; i < blk.num_params; ++i) {
      const Param& p = params[block_params[blk.first_param + i]];
      if (p.offset < 0) continue;
      for (int j = 0; j < blk.num_params; ++j) {
        const Param& q = params[block_params[blk.first_param + j]];
        if (q.offset < 0 || (i != j && p.offset > q.offset)) continue;
        for (int a = 0; a < p.size; ++a) {
          for (int b = i == j ? a : 0; b < q.size; ++b) f(i, j, a, b, p.offset + a, q.offset + b);
        }
      }
    }
  }

  /// Fill-reducing order of the unknown parameter blocks: approximate minimum degree on the
  /// block graph (Eigen's AMD), computed once per structure and applied to the offsets, so the
  /// normal equations are assembled already permuted and each factorisation needs no copy.
  void assignOffsets() {
    std::vector<int> var_of(params.size(), -1), param_of;
    for (std::size_t k = 0; k < params.size(); ++k) {
      if (params[k].offset >= 0) {
        var_of[k] = static_cast<int>(param_of.size());
        param_of.push_back(static_cast<int>(k));
      }
    }
    const int nv = static_cast<int>(param_of.size());
    std::vector<Eigen::Triplet<double, int>> graph;
    for (int v = 0; v < nv; ++v) graph.emplace_back(v, v, 1.0);
    for (const Block& blk : blocks) {
      for (int i = 0; i < blk.num_params; ++i) {
        const int vi = var_of[block_params[blk.first_param + i]];
        for (int j = 0; j < blk.num_params && vi >= 0; ++j) {
          const int vj = var_of[block_params[blk.first_param + j]];
          if (vj >= 0 && vi != vj) graph.emplace_back(vi, vj, 1.0);
        }
      }
    }
    Matrix g(nv, nv);
    g.setFromTriplets(graph.begin(), graph.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> elimination;
    Eigen::AMDOrdering<int> amd;
    amd(g, elimination);  // elimination.indices()[k]: the k-th block to eliminate
    num_unknowns = 0;
    for (int k = 0; k < nv; ++k) {
      Param& p = params[param_of[elimination.indices()[k]]];
      p.offset = num_unknowns;
      num_unknowns += p.size;
    }
  }

  void buildStructure() {
    assignOffsets();
    std::vector<Eigen::Triplet<double, int>> pattern;
    std::size_t max_res = 1, max_jac = 1, max_params = 1;
    for (const Block& blk : blocks) {
      forEachEntry(
          blk, [&](int, int, int, int, int row, int col) { pattern.emplace_back(row, col, 0.0); });
      max_res = std::max<std::size_t>(max_res, blk.num_residuals);
      std::size_t jac = 0;
      for (int i = 0; i < blk.num_params; ++i)
        jac += blk.num_residuals * params[block_params[blk.first_param + i]].size;
      max_jac = std::max(max_jac, jac);
      max_params = std::max<std::size_t>(max_params, blk.num_params);
    }
    for (int i = 0; i < num_unknowns; ++i) pattern.emplace_back(i, i, 0.0);
    hessian.resize(num_unknowns, num_unknowns);
    hessian.setFromTriplets(pattern.begin(), pattern.end());
    hessian.makeCompressed();
    slots.clear();
    for (Block& blk : blocks) {
      blk.first_slot = slots.size();
      forEachEntry(
          blk, [&](int, int, int, int, int row, int col) { slots.push_back(slotOf(row, col)); });
    }
    diagonal.resize(num_unknowns);
    for (int i = 0; i < num_unknowns; ++i) diagonal[i] = slotOf(i, i);
    gradient.resize(num_unknowns);
    residuals.resize(max_res);
    jacobian_storage.resize(max_jac);
    jacobians.resize(max_params);
    param_ptrs.resize(max_params);
    ldlt.analyzePattern(hessian);
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

  double cost() {
    double c = 0.0;
    for (const Block& blk : blocks) c += evaluateBlock(blk, false);
    return c;
  }

  /// Cost, Jᵀr and JᵀJ at the current parameters.
  double linearize() {
    double* h = hessian.valuePtr();
    std::fill(h, h + hessian.nonZeros(), 0.0);
    gradient.setZero();
    double c = 0.0;
    for (const Block& blk : blocks) {
      c += evaluateBlock(blk, true);
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
      const int* slot = slots.data() + blk.first_slot;
      for (int i = 0; i < blk.num_params; ++i) {
        const Param& p = params[block_params[blk.first_param + i]];
        if (p.offset < 0) continue;
        const double* Ji = jacobians[i];
        for (int j = 0; j < blk.num_params; ++j) {
          const Param& q = params[block_params[blk.first_param + j]];
          if (q.offset < 0 || (i != j && p.offset > q.offset)) continue;
          const double* Jj = jacobians[j];
          // Same visiting order as forEachEntry(), which laid out the slots.
          for (int a = 0; a < p.size; ++a) {
            for (int b = i == j ? a : 0; b < q.size; ++b) {
              double sum = 0.0;
              for (int k = 0; k < m; ++k) sum += Ji[k * p.size + a] * Jj[k * q.size + b];
              h[*slot++] += sum;
            }
          }
        }
      }
    }
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
  if (impl_->param_index.count(values) != 0) throw std::logic_error("parameter block added twice");
  impl_->param_index[values] = static_cast<int>(impl_->params.size());
  impl_->params.push_back({values, size, constant ? -1 : 0});
  impl_->structure_ready = false;
}

std::size_t SparseLm::addResidualBlock(const ceres::CostFunction* cost,
                                       const std::vector<double*>& params) {
  const auto& sizes = cost->parameter_block_sizes();
  if (sizes.size() != params.size()) throw std::logic_error("residual block: parameter count");
  Impl::Block blk{cost, impl_->block_params.size(), static_cast<int>(params.size()),
                  cost->num_residuals(), 0};
  for (std::size_t i = 0; i < params.size(); ++i) {
    const auto it = impl_->param_index.find(params[i]);
    if (it == impl_->param_index.end() || impl_->params[it->second].size != sizes[i]) {
      throw std::logic_error("residual block: undeclared or mis-sized parameter block");
    }
    impl_->block_params.push_back(it->second);
  }
  impl_->blocks.push_back(blk);
  impl_->structure_ready = false;
  return impl_->blocks.size() - 1;
}

double SparseLm::blockCost(std::size_t block) const {
  if (!impl_->structure_ready) const_cast<Impl&>(*impl_).buildStructure();
  return const_cast<Impl&>(*impl_).evaluateBlock(impl_->blocks[block], false);
}

std::size_t SparseLm::numUnknowns() const {
  if (!impl_->structure_ready) const_cast<Impl&>(*impl_).buildStructure();
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
  if (!options.carry_damping) m.lambda = kInitialLambda;
  double nu = 2.0;
  Eigen::VectorXd x_old, delta, h_delta;
  double* h = m.hessian.valuePtr();
  while (s.iterations < options.max_iterations) {
    if (options.should_stop && options.should_stop()) {
      s.stopped = true;
      break;
    }
    if (m.gradient.lpNorm<Eigen::Infinity>() < options.gradient_tolerance) break;
    for (int i = 0; i < m.num_unknowns; ++i) h[m.diagonal[i]] += m.lambda;
    m.ldlt.factorize(m.hessian);
    for (int i = 0; i < m.num_unknowns; ++i) h[m.diagonal[i]] -= m.lambda;
    ++s.iterations;
    if (m.ldlt.info() != Eigen::Success) {
      m.lambda = std::min(m.lambda * nu, kMaxLambda);
      nu *= 2.0;
      continue;
    }
    delta = m.ldlt.solve(-m.gradient);
    m.saveUnknowns(&x_old);
    if (delta.norm() < options.parameter_tolerance * (x_old.norm() + options.parameter_tolerance))
      break;
    // Predicted decrease of the linear model: −(gᵀδ + ½ δᵀHδ).
    h_delta = m.hessian.selfadjointView<Eigen::Upper>() * delta;
    const double model = -(m.gradient.dot(delta) + 0.5 * delta.dot(h_delta));
    m.setUnknowns(x_old + delta);
    const double new_cost = m.cost();
    const double rho = model > 0.0 ? (cost - new_cost) / model : -1.0;
    if (std::isfinite(new_cost) && rho > kMinRelativeDecrease) {
      ++s.accepted;
      const double t = 2.0 * rho - 1.0;
      m.lambda = std::max(m.lambda * std::max(1.0 / 3.0, 1.0 - t * t * t), kMinLambda);
      nu = 2.0;
      const double decrease = (cost - new_cost) / cost;
      cost = new_cost;
      if (decrease < options.function_tolerance) break;
      cost = m.linearize();
    } else {
      m.setUnknowns(x_old);
      m.lambda = std::min(m.lambda * nu, kMaxLambda);
      nu *= 2.0;
    }
  }
  s.final_cost = cost;
  return s;
}

}  // namespace coopnav
