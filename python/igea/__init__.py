"""igea: inertial guidance error analysis (Python bindings to libigea).

One function per job, numpy arrays in, frozen dataclasses out; failures of
the library raise IgeaError (code and message), wrong shapes ValueError;
bad data (an invalid argument, NaN, a sigma <= 0, ...) raise DataError, an
IgeaError that is also a ValueError.
"""
from ._lib import DataError, IgeaError, lib as _clib

__version__ = _clib.igea_version().decode()

from .threads import blas_threads  # noqa: E402

from .eqerr import EqerrResult, TestResult, accuracy_test, eqerr, pool  # noqa: E402
from .stats import chi2_cdf, chi2_quantile, chi2_sf, chi2_upper, normal_cdf, normal_quantile, union_size, verdict_thresholds  # noqa: E402,E501
from .stats import f_sf, normal_sf, t_quantile, t_sf  # noqa: E402
# -- further modules: one import line each, below --
from .redund import RedundGroup, RedundStability, redund_group, redund_stability  # noqa: E402
from .redund import FdiResult, GeometryReliability, Seed002Reliability, SeriesCheck, SkewCheck, confidence_distance, erfinv, false_alarm, fdi, fuse, fusion_set, parity_matrix, relation, reliability_diagram, reliability_exponential, reliability_geometry, reliability_kofn, reliability_parallel, reliability_seed002, reliability_series, series_check, simulate_redundant, skew_check, support, thresholds, transform  # noqa: E402,E501
from .stability import AllanResult, Block3Sigma, NoiseTerms, allan, block_3sigma, noise_id, octave_taus  # noqa: E402,E501
from .stability import NoiseFit, StabilityResult, noise_fit, stability, stability_taus  # noqa: E402,E501
from .regress import BayesResult, Collinearity, EbrResult, LsResult, PceResult, RidgeResult, RidgeTrace, bayes, bias_mse, collinearity, ebr, ls, pce, ridge, ridge_trace  # noqa: E402,E501
from .envfun import envfun, term_table  # noqa: E402
from .rls import RLS, RlsEpoch, RlsResult, rls_run  # noqa: E402
from .sim import Flight, MonteCarloPool, MonteCarloResult, montecarlo, reference_trajectory, simulate  # noqa: E402,E501
from .campaign import campaign, campaign_montecarlo  # noqa: E402
from .noise import NoiseEqerrResult  # noqa: E402
from .accel import AccelApplied, AccelCriterion, AccelHistory, AccelHistoryFit, AccelDesignInfo, AccelFit, AccelHysteresis, AccelIeeeFit, AccelJoint, AccelRefine, accel_analyze, accel_apply, accel_criterion, accel_fit_history, accel_history, accel_ieee_fit, accel_hysteresis, accel_joint, accel_combinations, accel_design, accel_fit, accel_merge, accel_refine, accel_schedule, accel_simulate, accel_to_g  # noqa: E402,E501
from .impact import Burnout, ImpactBudget, ImpactResult, burnout, cep, cep_approx, circle_prob, component_miss, impact, impact_budget  # noqa: E402,E501
from .triad import TriadResult, triad_apply, triad_calibrate, triad_fit, triad_static  # noqa: E402,E501
from .triad import GyroResult, triad_gyro_apply, triad_gyro_fit  # noqa: E402
from .io import MatrixFile, read_matrix  # noqa: E402
from .nav import NavResult, nav_ecef_to_geodetic, nav_geodetic_to_ecef, nav_gravity, nav_navigate, nav_site, nav_transform  # noqa: E402,E501
from .dw import DwResult, dw  # noqa: E402
from .inserr import NavErrors, NavErrorsLI, nav_errors, nav_errors_li  # noqa: E402
from .sim import RawFlight, simulate_raw, track_errors  # noqa: E402
