#include "coopnav/band/envelope_ldlt.hpp"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace coopnav {
namespace {

/// The factorisation's inner products, over [k0, k1). Their ranges are the rows' overlaps: a
/// few to a few dozen entries (bench_band, before the rows were narrowed to their first
/// non-zero: ~7 for one human, ~20 for five; fewer since), so a short range runs as two scalar
/// partial sums and a long one as four SSE2 ones; both orders are fixed, so the results are the
/// same on every run and every x86-64 machine (and on other machines, where the SSE2 path is the
/// same partial sums in scalar code).
constexpr int kVectorFrom = 8;

#if defined(__SSE2__)
double horizontalSum(__m128d a, __m128d b) {
  const __m128d s = _mm_add_pd(a, b);
  return _mm_cvtsd_f64(s) + _mm_cvtsd_f64(_mm_unpackhi_pd(s, s));
}
#endif

/// Σ x[k] y[k]. Always inlined: the factorisation calls it once per entry of L, and a call costs
/// more than the few products of a short range.
inline __attribute__((always_inline)) double dot(const double* x, const double* y, int k0, int k1) {
  if (k1 - k0 < kVectorFrom) {
    double a0 = 0.0, a1 = 0.0;
    int k = k0;
    for (; k + 2 <= k1; k += 2) {
      a0 += x[k] * y[k];
      a1 += x[k + 1] * y[k + 1];
    }
    if (k < k1) a0 += x[k] * y[k];
    return a0 + a1;
  }
#if defined(__SSE2__)
  __m128d a0 = _mm_setzero_pd(), a1 = _mm_setzero_pd();
  int k = k0;
  for (; k + 4 <= k1; k += 4) {
    a0 = _mm_add_pd(a0, _mm_mul_pd(_mm_loadu_pd(x + k), _mm_loadu_pd(y + k)));
    a1 = _mm_add_pd(a1, _mm_mul_pd(_mm_loadu_pd(x + k + 2), _mm_loadu_pd(y + k + 2)));
  }
  if (k + 2 <= k1) {
    a0 = _mm_add_pd(a0, _mm_mul_pd(_mm_loadu_pd(x + k), _mm_loadu_pd(y + k)));
    k += 2;
  }
  double r = horizontalSum(a0, a1);
#else
  double a00 = 0.0, a01 = 0.0, a10 = 0.0, a11 = 0.0;
  int k = k0;
  for (; k + 4 <= k1; k += 4) {
    a00 += x[k] * y[k];
    a01 += x[k + 1] * y[k + 1];
    a10 += x[k + 2] * y[k + 2];
    a11 += x[k + 3] * y[k + 3];
  }
  if (k + 2 <= k1) {
    a00 += x[k] * y[k];
    a01 += x[k + 1] * y[k + 1];
    k += 2;
  }
  double r = (a00 + a10) + (a01 + a11);
#endif
  if (k < k1) r += x[k] * y[k];
  return r;
}

/// Σ x[k] y[k] and Σ x[k] z[k] in one pass: two envelope columns against the same row, which
/// loads the row once for both (the factorisation is bound by its loads).
void dot2(const double* x, const double* y, const double* z, int k0, int k1, double* sy,
          double* sz) {
  if (k1 - k0 < kVectorFrom) {
    double a0 = 0.0, a1 = 0.0, b0 = 0.0, b1 = 0.0;
    int k = k0;
    for (; k + 2 <= k1; k += 2) {
      const double x0 = x[k], x1 = x[k + 1];
      a0 += x0 * y[k];
      a1 += x1 * y[k + 1];
      b0 += x0 * z[k];
      b1 += x1 * z[k + 1];
    }
    if (k < k1) {
      a0 += x[k] * y[k];
      b0 += x[k] * z[k];
    }
    *sy = a0 + a1;
    *sz = b0 + b1;
    return;
  }
#if defined(__SSE2__)
  __m128d a0 = _mm_setzero_pd(), a1 = _mm_setzero_pd(), b0 = _mm_setzero_pd(),
          b1 = _mm_setzero_pd();
  int k = k0;
  for (; k + 4 <= k1; k += 4) {
    const __m128d x0 = _mm_loadu_pd(x + k), x1 = _mm_loadu_pd(x + k + 2);
    a0 = _mm_add_pd(a0, _mm_mul_pd(x0, _mm_loadu_pd(y + k)));
    a1 = _mm_add_pd(a1, _mm_mul_pd(x1, _mm_loadu_pd(y + k + 2)));
    b0 = _mm_add_pd(b0, _mm_mul_pd(x0, _mm_loadu_pd(z + k)));
    b1 = _mm_add_pd(b1, _mm_mul_pd(x1, _mm_loadu_pd(z + k + 2)));
  }
  if (k + 2 <= k1) {
    const __m128d x0 = _mm_loadu_pd(x + k);
    a0 = _mm_add_pd(a0, _mm_mul_pd(x0, _mm_loadu_pd(y + k)));
    b0 = _mm_add_pd(b0, _mm_mul_pd(x0, _mm_loadu_pd(z + k)));
    k += 2;
  }
  double ry = horizontalSum(a0, a1), rz = horizontalSum(b0, b1);
  if (k < k1) {
    ry += x[k] * y[k];
    rz += x[k] * z[k];
  }
  *sy = ry;
  *sz = rz;
#else
  *sy = dot(x, y, k0, k1);
  *sz = dot(x, z, k0, k1);
#endif
}

/// y[k] −= a x[k] over [k0, k1), two lanes at a time (each y[k] gets the one product it would
/// get in scalar code: the same result on every machine).
void subtractScaled(double a, const double* x, double* y, int k0, int k1) {
  int k = k0;
#if defined(__SSE2__)
  const __m128d av = _mm_set1_pd(a);
  for (; k + 2 <= k1; k += 2) {
    _mm_storeu_pd(y + k, _mm_sub_pd(_mm_loadu_pd(y + k), _mm_mul_pd(av, _mm_loadu_pd(x + k))));
  }
#endif
  for (; k < k1; ++k) y[k] -= a * x[k];
}

}  // namespace

void EnvelopeLdlt::setPattern(std::vector<int> first) {
  first_ = std::move(first);
  const int n = static_cast<int>(first_.size());
  base_.assign(n, 0);
  int row_start = 0;  // row i's entries follow row i − 1's
  for (int i = 0; i < n; ++i) {
    base_[i] = row_start - first_[i];
    row_start += i - first_[i] + 1;
  }
  work_.assign(row_start, 0.0);
  lead_ = first_;
  d_.assign(n, 0.0);
  inv_d_.assign(n, 0.0);
}

void EnvelopeLdlt::narrowTo(const double* a) {
  const int n = static_cast<int>(first_.size());
  for (int i = 0; i < n; ++i) {
    const double* ai = a + base_[i];  // ai[j] = A(i, j)
    int f = first_[i];
    while (f < i && ai[f] == 0.0) ++f;
    lead_[i] = f;
  }
}

void EnvelopeLdlt::clear(double* a) const {
  const int n = static_cast<int>(first_.size());
  for (int i = 0; i < n; ++i) std::fill(a + base_[i] + lead_[i], a + base_[i] + i + 1, 0.0);
}

/// Row by row ("up-looking"): row i's entries come from inner products with the rows above it,
/// taken two columns at a time so that both share the loads of row i.
bool EnvelopeLdlt::factorize(const double* a, double lambda) {
  const int n = static_cast<int>(first_.size());
  for (int i = 0; i < n; ++i) {
    const int fi = lead_[i];
    const double* ai = a + base_[i];       // ai[j] = A(i, j)
    double* li = work_.data() + base_[i];  // li[j] = entry (i, j)
    // A is read where each entry is first written rather than copied beforehand: one pass
    // over the envelope less (the copy was 4 % of five humans' instructions; the time
    // difference is within bench_band's noise).
    // li[k] becomes w_k = L(i,k) D(k) for k < i: w_j = A(i,j) − Σ_{k<j} w_k L(j,k).
    int j = fi;
    for (; j + 1 < i; j += 2) {
      const int fj0 = lead_[j], fj1 = lead_[j + 1];
      const double* l0 = work_.data() + base_[j];
      const int k0 = std::max(fi, fj0);
      if (fj1 > j) {
        // Row j + 1 starts after column j: it shares no column below j + 1 with row i.
        li[j] = ai[j] - dot(li, l0, k0, j);
        li[j + 1] = ai[j + 1];
        continue;
      }
      const double* l1 = work_.data() + base_[j + 1];
      const int k1 = std::max(fi, fj1);
      // Both over [kc, j); the one that starts earlier adds its head alone.
      const int kc = std::max(k0, k1);
      // At most one head is not empty, and it is short: a plain loop costs less than dot()'s
      // dispatch.
      double head0 = 0.0, head1 = 0.0;
      for (int k = k0; k < kc; ++k) head0 += li[k] * l0[k];
      for (int k = k1; k < kc; ++k) head1 += li[k] * l1[k];
      double s0 = 0.0, s1 = 0.0;
      dot2(li, l0, l1, kc, j, &s0, &s1);
      li[j] = ai[j] - (head0 + s0);
      li[j + 1] = ai[j + 1] - ((head1 + s1) + li[j] * l1[j]);
    }
    for (; j < i; ++j) {
      const double* lj = work_.data() + base_[j];
      li[j] = ai[j] - dot(li, lj, std::max(fi, lead_[j]), j);
    }
    // Two partial sums: the subtraction chain is latency-bound in one.
    double d0 = ai[i] + lambda, d1 = 0.0;
    int k = fi;
    for (; k + 2 <= i; k += 2) {
      const double l0 = li[k] * inv_d_[k], l1 = li[k + 1] * inv_d_[k + 1];
      d0 -= li[k] * l0;
      d1 -= li[k + 1] * l1;
      li[k] = l0;
      li[k + 1] = l1;
    }
    if (k < i) {
      const double l = li[k] * inv_d_[k];
      d0 -= li[k] * l;
      li[k] = l;
    }
    const double d = d0 + d1;
    if (!(d > kMinPivot) || !std::isfinite(d)) return false;
    d_[i] = d;
    inv_d_[i] = 1.0 / d;
    li[i] = 1.0;
  }
  return true;
}

void EnvelopeLdlt::solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const {
  const int n = static_cast<int>(first_.size());
  *x = b;
  double* v = x->data();
  for (int i = 0; i < n; ++i) v[i] -= dot(work_.data() + base_[i], v, lead_[i], i);
  for (int i = 0; i < n; ++i) v[i] /= d_[i];
  for (int i = n - 1; i >= 0; --i) subtractScaled(v[i], work_.data() + base_[i], v, lead_[i], i);
}

}  // namespace coopnav
