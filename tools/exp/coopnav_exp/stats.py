"""Intervals and paired tests for study tables (numpy only; no SciPy on Debian's base).

- Proportions: the Wilson score interval (Wilson 1927), right at 0 and n events where the normal
  approximation gives zero width.
- Means, medians, ratios of sums and AUCs: the percentile bootstrap (Efron & Tibshirani 1993,
  ch. 13) with a fixed seed, so the same data give the same table to the last digit.
- Two variants on the same encounters: the paired bootstrap of the mean difference, the Wilcoxon
  signed-rank test (exact below 50 pairs without ties, else the normal approximation with the tie
  correction) for continuous metrics, and the exact McNemar test for outcomes.
- Agreement of two measures: Spearman's rank correlation (average ranks for ties), with a
  bootstrap interval over the cases.

Every function takes plain sequences, drops nothing silently: non-finite values are the caller's
to filter (`finite_pairs`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

Z95 = 1.959963984540054  # the standard normal's 97.5 % quantile
DEFAULT_SEED = 49
DEFAULT_N_BOOT = 2000


@dataclass(frozen=True)
class Interval:
    """An estimate with its interval; n is the number of cases it stands on."""

    value: float
    lo: float
    hi: float
    n: int

    def as_dict(self) -> dict:
        return {"value": _num(self.value), "lo": _num(self.lo), "hi": _num(self.hi), "n": self.n}


def _num(x: float) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _z(confidence: float) -> float:
    if abs(confidence - 0.95) < 1e-12:
        return Z95
    # Inverse of the normal CDF by bisection on math.erf (no SciPy): plenty for a quantile.
    target = 0.5 + confidence / 2.0
    lo, hi = 0.0, 10.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if 0.5 * (1.0 + math.erf(mid / math.sqrt(2.0))) < target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def wilson(successes: int, n: int, confidence: float = 0.95) -> Interval:
    """Wilson score interval of successes / n; NaN with n 0."""
    if n <= 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    if not 0 <= successes <= n:
        raise ValueError(f"wilson: {successes} successes out of {n}")
    z = _z(confidence)
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    # At 0 and n events the bounds are exactly 0 and 1 (rounding would leave 1e-17).
    lo = 0.0 if successes == 0 else max(0.0, centre - half)
    hi = 1.0 if successes == n else min(1.0, centre + half)
    return Interval(p, lo, hi, n)


def _rng(seed: int) -> np.random.Generator:
    return np.random.default_rng(seed)


def bootstrap(values: Sequence[float], statistic: Callable[[np.ndarray], float] = np.mean, *,
              n_boot: int = DEFAULT_N_BOOT, seed: int = DEFAULT_SEED,
              confidence: float = 0.95) -> Interval:
    """Percentile bootstrap interval of statistic(values), resampling the values."""
    x = np.asarray(values, dtype=float)
    n = len(x)
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    estimate = float(statistic(x))
    idx = _rng(seed).integers(0, n, size=(n_boot, n))
    reps = np.array([statistic(x[i]) for i in idx], dtype=float)
    return _percentile(estimate, reps, confidence, n)


def _percentile(estimate: float, reps: np.ndarray, confidence: float, n: int) -> Interval:
    reps = reps[np.isfinite(reps)]
    if len(reps) == 0:
        return Interval(estimate, math.nan, math.nan, n)
    alpha = (1.0 - confidence) / 2.0
    lo, hi = np.quantile(reps, [alpha, 1.0 - alpha])
    return Interval(estimate, float(lo), float(hi), n)


def bootstrap_ratio(numerators: Sequence[float], denominators: Sequence[float], *,
                    n_boot: int = DEFAULT_N_BOOT, seed: int = DEFAULT_SEED,
                    confidence: float = 0.95) -> Interval:
    """Σ numerator / Σ denominator over cases, resampling cases (numerator and denominator
    together), e.g. time to goal over the robot-alone baseline's."""
    a = np.asarray(numerators, dtype=float)
    b = np.asarray(denominators, dtype=float)
    if a.shape != b.shape:
        raise ValueError("bootstrap_ratio: numerators and denominators differ in length")
    n = len(a)
    if n == 0 or b.sum() == 0:
        return Interval(math.nan, math.nan, math.nan, n)
    estimate = float(a.sum() / b.sum())
    idx = _rng(seed).integers(0, n, size=(n_boot, n))
    with np.errstate(divide="ignore", invalid="ignore"):
        reps = a[idx].sum(axis=1) / b[idx].sum(axis=1)
    return _percentile(estimate, reps, confidence, n)


def auc(scores: Sequence[float], labels: Sequence[bool]) -> float:
    """Area under the ROC curve = P(score of a positive > score of a negative) + ½ P(tie)
    (Mann-Whitney); NaN without both classes."""
    s = np.asarray(scores, dtype=float)
    y = np.asarray(labels, dtype=bool)
    return _auc_of(s[y], s[~y])


def _auc_of(pos: np.ndarray, neg: np.ndarray) -> float:
    # Mann-Whitney U from the average ranks of both together (ties count ½): O(n log n).
    p, q = len(pos), len(neg)
    if p == 0 or q == 0:
        return math.nan
    r = ranks(np.concatenate([pos, neg]))
    return float((r[:p].sum() - p * (p + 1) / 2.0) / (p * q))


def bootstrap_auc(scores: Sequence[float], labels: Sequence[bool], *,
                  n_boot: int = DEFAULT_N_BOOT, seed: int = DEFAULT_SEED,
                  confidence: float = 0.95) -> Interval:
    """AUC with a percentile interval from resampling the positives and the negatives each
    (stratified: every resample keeps both classes and their counts)."""
    s = np.asarray(scores, dtype=float)
    y = np.asarray(labels, dtype=bool)
    pos, neg = s[y], s[~y]
    n = len(s)
    estimate = auc(s, y)
    if math.isnan(estimate):
        return Interval(math.nan, math.nan, math.nan, n)
    rng = _rng(seed)
    reps = np.empty(n_boot)
    for b in range(n_boot):
        reps[b] = _auc_of(pos[rng.integers(0, len(pos), len(pos))],
                          neg[rng.integers(0, len(neg), len(neg))])
    return _percentile(estimate, reps, confidence, n)


def ranks(values: Sequence[float]) -> np.ndarray:
    """Ranks 1..n, ties given their average rank."""
    x = np.asarray(values, dtype=float)
    if len(x) == 0:
        return np.empty(0)
    _, inverse, counts = np.unique(x, return_inverse=True, return_counts=True)
    ends = np.cumsum(counts)  # a group of equal values holds ranks ends-counts+1 .. ends
    return ((ends - counts + 1 + ends) / 2.0)[inverse]


def spearman(x: Sequence[float], y: Sequence[float]) -> float:
    """Spearman's ρ: Pearson's correlation of the average ranks; NaN when either is constant."""
    if len(x) != len(y):
        raise ValueError("spearman: x and y differ in length")
    if len(x) < 2:
        return math.nan
    rx, ry = ranks(x), ranks(y)
    rx, ry = rx - rx.mean(), ry - ry.mean()
    den = math.sqrt(float((rx * rx).sum() * (ry * ry).sum()))
    return math.nan if den == 0 else float((rx * ry).sum() / den)


def bootstrap_spearman(x: Sequence[float], y: Sequence[float], *, n_boot: int = DEFAULT_N_BOOT,
                       seed: int = DEFAULT_SEED, confidence: float = 0.95) -> Interval:
    """Spearman's ρ with a percentile interval from resampling the (x, y) pairs."""
    a = np.asarray(x, dtype=float)
    b = np.asarray(y, dtype=float)
    n = len(a)
    estimate = spearman(a, b)
    if n < 2:
        return Interval(estimate, math.nan, math.nan, n)
    idx = _rng(seed).integers(0, n, size=(n_boot, n))
    reps = np.array([spearman(a[i], b[i]) for i in idx])
    return _percentile(estimate, reps, confidence, n)


@dataclass(frozen=True)
class PairedResult:
    """Variant B minus variant A on the same encounters."""

    mean_difference: Interval  # paired bootstrap of mean(b - a)
    p_value: float             # two-sided
    test: str                  # "wilcoxon-exact", "wilcoxon-normal", "mcnemar-exact", ...
    n_pairs: int

    def as_dict(self) -> dict:
        return {"mean_difference": self.mean_difference.as_dict(), "p_value": _num(self.p_value),
                "test": self.test, "n_pairs": self.n_pairs}


def paired_bootstrap(a: Sequence[float], b: Sequence[float], *, n_boot: int = DEFAULT_N_BOOT,
                     seed: int = DEFAULT_SEED, confidence: float = 0.95) -> tuple[Interval, float]:
    """Mean of b - a over pairs with a percentile interval, and the two-sided bootstrap p-value
    (twice the share of resampled means on the far side of 0, at most 1)."""
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    n = len(d)
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0), math.nan
    idx = _rng(seed).integers(0, n, size=(n_boot, n))
    reps = d[idx].mean(axis=1)
    interval = _percentile(float(d.mean()), reps, confidence, n)
    if np.all(d == 0):
        return interval, 1.0
    far = min((reps <= 0).mean(), (reps >= 0).mean())
    return interval, float(min(1.0, 2.0 * far))


def _normal_sf(z: float) -> float:
    return 0.5 * math.erfc(z / math.sqrt(2.0))


def wilcoxon_signed_rank(a: Sequence[float], b: Sequence[float]) -> tuple[float, float, str]:
    """Wilcoxon signed-rank test of b - a (zero differences dropped, Wilcoxon's convention):
    returns (W+, two-sided p, method). Exact by enumerating the rank-sum distribution when there
    are fewer than 50 non-zero differences and no ties; else the normal approximation with the
    tie correction and a continuity correction of ½."""
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    d = d[d != 0]
    n = len(d)
    if n == 0:
        return 0.0, 1.0, "wilcoxon-none"
    r = ranks(np.abs(d))
    w_plus = float(r[d > 0].sum())
    total = n * (n + 1) / 2.0
    tied = len(np.unique(np.abs(d))) < n
    if n < 50 and not tied:
        # counts[s] = number of sign assignments with W+ = s (ranks 1..n).
        counts = np.zeros(int(total) + 1)
        counts[0] = 1
        for k in range(1, n + 1):
            shifted = np.zeros_like(counts)
            shifted[k:] = counts[:-k]
            counts = counts + shifted
        prob = counts / counts.sum()
        w = int(round(w_plus))
        lower = prob[: w + 1].sum()
        upper = prob[w:].sum()
        return w_plus, float(min(1.0, 2.0 * min(lower, upper))), "wilcoxon-exact"
    mean = total / 2.0
    _, tie_counts = np.unique(np.abs(d), return_counts=True)
    var = n * (n + 1) * (2 * n + 1) / 24.0 - float((tie_counts ** 3 - tie_counts).sum()) / 48.0
    if var <= 0:
        return w_plus, 1.0, "wilcoxon-normal"
    z = (abs(w_plus - mean) - 0.5) / math.sqrt(var)
    return w_plus, float(min(1.0, 2.0 * _normal_sf(max(z, 0.0)))), "wilcoxon-normal"


def mcnemar_exact(a: Sequence[bool], b: Sequence[bool]) -> tuple[int, int, float]:
    """Exact McNemar test on paired outcomes: (a only, b only, two-sided p), the binomial test of
    the discordant pairs at ½."""
    x = np.asarray(a, dtype=bool)
    y = np.asarray(b, dtype=bool)
    only_a = int((x & ~y).sum())
    only_b = int((~x & y).sum())
    m = only_a + only_b
    if m == 0:
        return only_a, only_b, 1.0
    k = min(only_a, only_b)
    tail = sum(math.comb(m, i) for i in range(k + 1)) / 2.0 ** m
    return only_a, only_b, float(min(1.0, 2.0 * tail))


def paired_compare(a: Sequence[float], b: Sequence[float], *, binary: bool = False,
                   n_boot: int = DEFAULT_N_BOOT, seed: int = DEFAULT_SEED) -> PairedResult:
    """Variant b against variant a on the same encounters: the paired bootstrap interval of the
    mean difference, and McNemar (binary outcomes) or Wilcoxon's p-value."""
    interval, _ = paired_bootstrap(np.asarray(a, dtype=float), np.asarray(b, dtype=float),
                                   n_boot=n_boot, seed=seed)
    if binary:
        _, _, p = mcnemar_exact(a, b)
        return PairedResult(interval, p, "mcnemar-exact", len(a))
    _, p, method = wilcoxon_signed_rank(a, b)
    return PairedResult(interval, p, method, len(a))


def finite_pairs(x: Sequence[float | None], y: Sequence[float | None]) -> tuple[list, list]:
    """The pairs where both values are finite numbers (None, NaN, inf dropped together)."""
    keep_x, keep_y = [], []
    for u, v in zip(x, y):
        if u is None or v is None:
            continue
        if isinstance(u, bool) or isinstance(v, bool):
            u, v = float(u), float(v)
        if math.isfinite(u) and math.isfinite(v):
            keep_x.append(float(u))
            keep_y.append(float(v))
    return keep_x, keep_y
