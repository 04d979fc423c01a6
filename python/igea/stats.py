"""Normal and chi-square distributions (validated; GSL never aborts)."""
import ctypes

from . import _lib


def _scalar(fn, where, *args):
    out = ctypes.c_double()
    _lib.call(where, fn, *args, ctypes.byref(out))
    return out.value


def normal_cdf(x):
    """Phi(x), the standard normal cdf."""
    return _scalar("igea_stats_normal_cdf", "igea.normal_cdf", float(x))


def normal_sf(x):
    """Upper tail Q(x) = 1 - Phi(x), relatively accurate down to the
    smallest positive double (x about 38.5); igea_stats_normal_sf."""
    return _scalar("igea_stats_normal_sf", "igea.normal_sf", float(x))


def normal_quantile(p):
    """Lower quantile Phi^-1(p), 0 < p < 1."""
    return _scalar("igea_stats_normal_quantile", "igea.normal_quantile", float(p))


def chi2_cdf(x, dof):
    """P(x; dof), 0 < dof <= 1e7 (relative error below 1e-14 up to dof 1e5)."""
    return _scalar("igea_stats_chi2_cdf", "igea.chi2_cdf", float(x), float(dof))


def chi2_sf(x, dof):
    """Q(x; dof) = 1 - P(x; dof): the p-value of a chi-square statistic x."""
    return _scalar("igea_stats_chi2_sf", "igea.chi2_sf", float(x), float(dof))


def chi2_quantile(p, dof):
    """Lower quantile: P(x; dof) = p."""
    return _scalar("igea_stats_chi2_quantile", "igea.chi2_quantile", float(p), float(dof))


def chi2_upper(alpha, dof):
    """Upper alpha point chi2_alpha(dof) (the seed's notation): Q(x; dof) = alpha."""
    return _scalar("igea_stats_chi2_upper", "igea.chi2_upper", float(alpha), float(dof))


def t_sf(t, dof):
    """Student's t upper tail P(T > t); igea_stats_t_sf."""
    return _scalar("igea_stats_t_sf", "igea.t_sf", float(t), float(dof))


def t_quantile(p, dof):
    """Lower quantile of Student's t: P(T <= t) = p; igea_stats_t_quantile."""
    return _scalar("igea_stats_t_quantile", "igea.t_quantile", float(p), float(dof))


def f_sf(f, d1, d2):
    """F distribution upper tail P(F > f; d1, d2); igea_stats_f_sf."""
    return _scalar("igea_stats_f_sf", "igea.f_sf", float(f), float(d1), float(d2))


def union_size(n, a, b):
    """P(max |z_i| > a or sum z_i^2 > b) for n independent N(0, 1): the
    true size of the overall verdict with thresholds a, b (either may be
    inf: no component test, no chi-square test); igea_stats_union_size."""
    return _scalar("igea_stats_union_size", "igea.union_size", int(n), float(a), float(b))


def verdict_thresholds(rule, n, alpha=0.01):
    """(a, b, size) of the overall verdict rule "seed", "chi2", "exact" or
    "sidak" for n tested components at level alpha: |z_i| > a or
    sum z_i^2 > b rejects, size is the rule's true false-alarm
    probability; igea_stats_verdict_thresholds."""
    from . import _capi
    code = _lib.choice(_capi.CHOICE_STATS_VERDICT, rule, "igea.verdict_thresholds", "rule")
    a, b, s = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
    _lib.call("igea.verdict_thresholds", "igea_stats_verdict_thresholds", code, int(n),
              float(alpha), ctypes.byref(a), ctypes.byref(b), ctypes.byref(s))
    return a.value, b.value, s.value
