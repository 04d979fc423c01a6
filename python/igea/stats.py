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


def normal_quantile(p):
    """Lower quantile Phi^-1(p), 0 < p < 1."""
    return _scalar("igea_stats_normal_quantile", "igea.normal_quantile", float(p))


def chi2_cdf(x, dof):
    """P(x; dof)."""
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
