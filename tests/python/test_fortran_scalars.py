"""The Fortran module's SCALARS table (python/gen_fortran.py): a writable
int or double pointer of an exported function is an assumed-size array
x(*) unless the table lists it as pointing at one value. A scalar output
left out of the table is an array dummy in Fortran, which a caller's
scalar variable cannot be passed to. The table is kept by hand; this test
keeps it from drifting: every writable pointer whose header comment gives
it no size (name[n], (n), "n values", "3 ntrk", ...) must be in SCALARS or
in ARRAYS below, the pointers read as arrays although their comment does
not size them in those words. A new function's output therefore fails
here until it is put in one of the two."""
import glob
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "python"))
import gen_capi  # noqa: E402
import gen_fortran  # noqa: E402

# Arrays whose size the header states in other words (a row of outputs
# named together, "2 outputs", a layout by reference to another
# function, an options or state array); each was read in its header.
ARRAYS = {
    ('igea_accel_history_full', 'beta0'),
    ('igea_normal_accumulate_threads', 'A'),
    ('igea_normal_accumulate_threads', 'b'),
    ('igea_normal_accumulate_threads', 'wtw'),
    ('igea_eqerr_accumulate', 'A'),
    ('igea_eqerr_accumulate', 'b'),
    ('igea_eqerr_accumulate', 'wtw'),
    ('igea_stability_fit_boot', 'lo'),
    ('igea_envfun_compute_site', 'S'),
    ('igea_impact_component_miss', 'miss'),
    ('igea_sim_raw_track', 'q0'),
    ('igea_sim_raw_track', 'site_out'),
    ('igea_sim_raw_track', 'tel'),
    ('igea_sim_raw_track', 'trk'),
    ('igea_sim_track_errors', 'acc'),
    ('igea_sim_track_errors', 'err'),
    ('igea_triad_gyro_apply', 'cal'),
    ('igea_accel_merge', 'theta_deg'),
    ('igea_accel_merge', 'ya_mean'),
    ('igea_accel_design', 'A'),
    ('igea_accel_hysteresis', 'theta_deg'),
    ('igea_accel_hysteresis', 'diff'),
    ('igea_choice_codes', 'codes'),
    ('igea_dw_compute', 'dw'),
    ('igea_dw_compute', 'dw_dtau'),
    ('igea_dw_summary', 'sigma'),
    ('igea_envfun_default_terms', 'terms'),
    ('igea_envfun_nonlinear', 'dW'),
    ('igea_eqerr_solve_qr', 'lambda'),
    ('igea_eqerr_solve_qr', 'P'),
    ('igea_eqerr_solve_qr', 'equiv_err'),
    ('igea_eqerr_solve_qr', 'z'),
    ('igea_eqerr_solve_qr', 'reject'),
    ('igea_eqerr_solve_qr', 'info'),
    ('igea_eqerr_run', 'lambda'),
    ('igea_eqerr_run', 'P'),
    ('igea_eqerr_run', 'equiv_err'),
    ('igea_eqerr_run', 'reject'),
    ('igea_eqerr_run', 'info'),
    ('igea_nav_geodetic_to_ecef', 'r'),
    ('igea_nav_ecef_to_geodetic', 'geo'),
    ('igea_nav_transform', 'r_out'),
    ('igea_nav_transform', 'v_out'),
    ('igea_nav_rotation', 'M'),
    ('igea_nav_gravity', 'g'),
    ('igea_nav_gravity', 'G'),
    ('igea_nav_gravity_li', 'g'),
    ('igea_nav_gravity_li', 'G'),
    ('igea_nav_init', 'state'),
    ('igea_whiten_accumulate', 'A'),
    ('igea_whiten_accumulate', 'wtw'),
    ('igea_whiten_accumulate', 'white'),
    ('igea_noise_ar_fit', 'phi'),
    ('igea_noise_ar_fit', 'se'),
    ('igea_noise_vce', 'scale'),
    ('igea_noise_vce', 'se'),
    ('igea_noise_vce', 'redund'),
    ('igea_noise_eqerr', 'lambda'),
    ('igea_noise_eqerr', 'P'),
    ('igea_noise_eqerr', 'equiv_err'),
    ('igea_noise_eqerr', 'z'),
    ('igea_noise_eqerr', 'reject'),
    ('igea_noise_eqerr', 'row_w'),
    ('igea_noise_eqerr_resid', 'lambda'),
    ('igea_noise_eqerr_resid', 'P'),
    ('igea_noise_eqerr_resid', 'equiv_err'),
    ('igea_noise_eqerr_resid', 'z'),
    ('igea_noise_eqerr_resid', 'reject'),
    ('igea_noise_eqerr_resid', 'info'),
    ('igea_noise_eqerr_resid', 'row_w'),
    ('igea_noise_eqerr_resid', 'resid'),
    ('igea_whiten_accumulate_xcov', 'A'),
    ('igea_whiten_accumulate_xcov', 'b'),
    ('igea_whiten_accumulate_xcov', 'wtw'),
    ('igea_whiten_accumulate_xcov', 'white'),
    ('igea_noise_eqerr_xcov', 'lambda'),
    ('igea_noise_eqerr_xcov', 'P'),
    ('igea_noise_eqerr_xcov', 'equiv_err'),
    ('igea_noise_eqerr_xcov', 'z'),
    ('igea_noise_eqerr_xcov', 'reject'),
    ('igea_noise_eqerr_xcov', 'info'),
    ('igea_noise_eqerr_xcov', 'row_w'),
    ('igea_noise_eqerr_xcov', 'resid'),
    ('igea_normal_accumulate', 'A'),
    ('igea_normal_accumulate', 'b'),
    ('igea_redund_diagram', 'Rblock'),
    ('igea_redund_relation_delta', 'r'),
    ('igea_redund_monitor', 'fused'),
    ('igea_sim_trajectory', 'traj'),
    ('igea_sim_model_get_sigma', 'track_sigma'),
    ('igea_sim_model_get_spec', 'spec_sigma'),
    ('igea_sim_flight', 'x_true'),
    ('igea_sim_flight', 'dw'),
    ('igea_sim_nonlinear', 'dW'),
    ('igea_sim_interval', 'lohi'),
    ('igea_sim_montecarlo', 'comp_tested'),
    ('igea_sim_montecarlo', 'comp_reject'),
    ('igea_sim_montecarlo_ex', 'counts'),  # its arguments 1-12 are igea_sim_montecarlo's
    ('igea_sim_montecarlo_ex', 'rates'),
    ('igea_sim_montecarlo_ex', 'comp_tested'),
    ('igea_sim_montecarlo_ex', 'comp_reject'),
    ('igea_sim_montecarlo_ex', 'table'),
    ('igea_sim_raw', 'tel'),
    ('igea_sim_raw', 'trk'),
    ('igea_sim_raw', 'q0'),
    ('igea_sim_raw', 'site_out'),
    ('igea_stability_allan', 'lo'),
    ('igea_stability_allan', 'hi'),
    ('igea_stability_allan', 'edf'),
    ('igea_stability_octave_taus', 'tau'),
    ('igea_stability_noise_id', 'out'),
    ('igea_stability_dev', 'lo'),
    ('igea_stability_dev', 'hi'),
    ('igea_stability_dev', 'edf'),
    ('igea_stability_dev', 'tau_used'),
    ('igea_stats_pool', 'info'),
    ('igea_stats_diag_add', 'state'),
    ('igea_triad_apply', 'cal'),
}


def _comment(texts, hdr, name):
    t = texts[hdr]
    i = t.find(name + "(")
    j = t.rfind("*/", 0, i)
    return t[t.rfind("/*", 0, j):j]


def unsized():
    """(function, argument) of the writable int/double pointers that are
    not in SCALARS and whose header comment gives them no size."""
    texts = {os.path.basename(f): open(f).read()
             for f in glob.glob(os.path.join(gen_capi.INCLUDE, "**", "*.h"), recursive=True)}
    out = set()
    for hdr, _, name, params in gen_capi.parse()[1]:
        com = _comment(texts, hdr, name)
        sc = gen_fortran.SCALARS.get(name, "").split()
        for ct, p in params:
            if ct.replace(" ", "") not in ("int*", "double*") or p in sc:
                continue
            q = re.escape(p)
            if re.search(r"\b%s\s*(\[|\(\s*[\w+*\- ]+\)|: *\w+ x|\(\w+ x)" % q, com) or \
               re.search(r"\b%s\b[^,;.]{0,40}(values|doubles|ints|entries|x \w|LEN|\bn\b|rows|"
                         r"array|per )" % q, com):
                continue
            out.add((name, p))
    return out


def test_every_unsized_pointer_is_classified():
    new = sorted(unsized() - ARRAYS)
    assert not new, ("pointer arguments whose header comment gives no size: add each to "
                     "gen_fortran.SCALARS if it points at one value, else to ARRAYS here: %s"
                     % new)


def test_no_stale_entries():
    params = {name: {pn for _, pn in ps} for _, _, name, ps in gen_capi.parse()[1]}
    stale = sorted((f, p) for f, p in ARRAYS if p not in params.get(f, ()))
    assert not stale, stale
    both = sorted((f, p) for f, p in ARRAYS if p in gen_fortran.SCALARS.get(f, "").split())
    assert not both, both


def test_scalar_outputs_found_in_the_headers():
    """The outputs this table had missed, each documented as one value in
    its header: now scalars in the module."""
    src = gen_fortran.generate()
    for fname, arg in [("igea_rls_get_q", "q"), ("igea_stats_normal_sf", "q"),
                       ("igea_stability_taus", "ntau"), ("igea_envfun_all_terms", "n"),
                       ("igea_whiten_get_state", "group"), ("igea_dw_compute", "bad")]:
        body = src[src.index("function %s(" % fname):]
        body = body[:body.index("end function")]
        decl = [l for l in body.splitlines() if re.search(r"::\s*%s(\(\*\))?\s*$" % arg, l)]
        assert decl and not decl[0].rstrip().endswith("(*)"), (fname, arg, decl)
