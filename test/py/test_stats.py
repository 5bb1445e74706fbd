"""coopnav_exp.stats on hand-computed cases (intervals, AUC, ranks, paired tests)."""

import math

import numpy as np
import pytest

from coopnav_exp import stats


def test_wilson_at_zero_half_and_all():
    # 0/20: [0, z²/(n + z²)] = [0, 3.8415/23.8415].
    iv = stats.wilson(0, 20)
    assert iv.value == 0.0 and iv.lo == 0.0
    assert iv.hi == pytest.approx(3.841458820694124 / 23.841458820694124, abs=1e-12)
    assert iv.hi == pytest.approx(0.1611, abs=1e-4)
    # 10/20: 0.5 ± z sqrt(0.25/20 + z²/1600) / (1 + z²/20) = [0.2993, 0.7007].
    iv = stats.wilson(10, 20)
    assert (iv.lo, iv.hi) == (pytest.approx(0.29929, abs=1e-5), pytest.approx(0.70071, abs=1e-5))
    iv = stats.wilson(20, 20)
    assert iv.hi == 1.0 and iv.lo == pytest.approx(1 - 0.161125, abs=1e-5)
    assert math.isnan(stats.wilson(0, 0).value)
    with pytest.raises(ValueError):
        stats.wilson(3, 2)


def test_normal_quantile_for_other_levels():
    assert stats._z(0.90) == pytest.approx(1.644854, abs=1e-6)


def test_bootstrap_is_seeded_and_exact_on_constants():
    assert stats.bootstrap([2.0] * 7).as_dict() == {"value": 2.0, "lo": 2.0, "hi": 2.0, "n": 7}
    x = [0.1, 0.5, 0.2, 0.9, 0.4, 0.3]
    a, b = stats.bootstrap(x, seed=3), stats.bootstrap(x, seed=3)
    assert a == b
    assert a.value == pytest.approx(np.mean(x))
    assert min(x) <= a.lo < a.value < a.hi <= max(x)
    assert math.isnan(stats.bootstrap([]).value)


def test_bootstrap_ratio_of_sums():
    iv = stats.bootstrap_ratio([2.0, 4.0, 6.0], [1.0, 2.0, 3.0])
    assert iv.value == pytest.approx(2.0)
    assert iv.lo == pytest.approx(2.0) and iv.hi == pytest.approx(2.0)  # every case is 2
    with pytest.raises(ValueError):
        stats.bootstrap_ratio([1.0], [1.0, 2.0])


def test_auc_counts_pairs_and_half_ties():
    # Positives 0.35, 0.8 against negatives 0.1, 0.4: 3 of 4 pairs ordered.
    assert stats.auc([0.1, 0.4, 0.35, 0.8], [False, False, True, True]) == 0.75
    assert stats.auc([1.0, 1.0], [True, False]) == 0.5
    assert math.isnan(stats.auc([1.0, 2.0], [True, True]))
    iv = stats.bootstrap_auc([0.1, 0.2, 0.8, 0.9], [False, False, True, True])
    assert iv.value == 1.0 and iv.lo == 1.0 and iv.hi == 1.0  # separable in every resample


def test_ranks_and_spearman():
    assert list(stats.ranks([10, 20, 20, 30])) == [1.0, 2.5, 2.5, 4.0]
    # Ranks (1,2,3) against (1,3,2): Σ d_x d_y = 1 over sqrt(2 × 2).
    assert stats.spearman([1, 2, 3], [1, 3, 2]) == pytest.approx(0.5)
    assert stats.spearman([1, 2, 3, 4], [8, 6, 4, 2]) == pytest.approx(-1.0)
    assert math.isnan(stats.spearman([1, 1, 1], [1, 2, 3]))
    iv = stats.bootstrap_spearman([1, 2, 3, 4, 5], [2, 4, 6, 8, 10])
    assert iv.value == pytest.approx(1.0)


def test_wilcoxon_exact_small_samples():
    # All five differences positive: W+ = 15, P = 2 / 2^5.
    w, p, method = stats.wilcoxon_signed_rank([0] * 5, [1, 2, 3, 4, 5])
    assert (w, method) == (15.0, "wilcoxon-exact") and p == pytest.approx(0.0625)
    # Rank 1 negative: W+ = 14, P(W+ >= 14) = 2/32, two-sided 0.125.
    w, p, _ = stats.wilcoxon_signed_rank([0] * 5, [-1, 2, 3, 4, 5])
    assert w == 14.0 and p == pytest.approx(0.125)
    # Zero differences are dropped; none left: p 1.
    assert stats.wilcoxon_signed_rank([1, 2], [1, 2])[1] == 1.0


def test_wilcoxon_normal_with_ties():
    a = [0.0] * 60
    b = [1.0] * 30 + [-1.0] * 30  # symmetric: W+ = its mean, p = 1
    w, p, method = stats.wilcoxon_signed_rank(a, b)
    assert method == "wilcoxon-normal"
    assert w == pytest.approx(30 * 30.5) and p == pytest.approx(1.0)


def test_mcnemar_exact():
    a = [True] * 4 + [False] * 6 + [True] * 10
    b = [True] * 4 + [True] * 6 + [True] * 10  # b only: 6, a only: 0 -> 2 / 2^6
    assert stats.mcnemar_exact(a, b) == (0, 6, pytest.approx(0.03125))
    assert stats.mcnemar_exact([True], [True])[2] == 1.0


def test_paired_compare():
    a = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    r = stats.paired_compare(a, [x + 1.0 for x in a])
    assert r.mean_difference.value == 1.0 and r.mean_difference.lo == 1.0
    assert r.test == "wilcoxon-normal"  # six equal differences are ties
    assert r.p_value < 0.05
    r = stats.paired_compare([0, 0, 0, 0], [1, 1, 1, 1], binary=True)
    assert r.test == "mcnemar-exact" and r.p_value == pytest.approx(0.125)
    interval, p = stats.paired_bootstrap([1.0, 2.0], [1.0, 2.0])
    assert interval.value == 0.0 and p == 1.0


def test_finite_pairs_drop_together():
    x, y = stats.finite_pairs([1.0, None, 3.0, float("nan"), True], [2.0, 5.0, None, 1.0, 0.5])
    assert (x, y) == ([1.0, 1.0], [2.0, 0.5])
