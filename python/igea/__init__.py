"""igea: inertial guidance error analysis (Python bindings to libigea).

One function per job, numpy arrays in, frozen dataclasses out; failures of
the library raise IgeaError (code and message), wrong shapes ValueError.
"""
from ._lib import IgeaError, lib as _clib

__version__ = _clib.igea_version().decode()

from .eqerr import EqerrResult, TestResult, accuracy_test, eqerr, pool  # noqa: E402
from .stats import chi2_cdf, chi2_quantile, chi2_sf, chi2_upper, normal_cdf, normal_quantile  # noqa: E402
# -- further modules: one import line each, below --
