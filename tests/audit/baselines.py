"""Valid baseline calls of the exported functions, for gen_invalid.py.

A parameter's value is taken, in order, from the function's entry in BASE,
from NAME_DEFAULTS (by parameter name), or from its type: a writable
pointer is an output ('out'), an igea_rls * a fresh handle ('h'), an
igea_rls ** a handle output ('ho'). A function whose every parameter is
resolved so needs no entry; the generator stops when one cannot be.

Values:
  scalars    a C expression; it may name the function's other scalars
  pointers   'out'         output, filled with a byte pattern
             'NULL'        passed as NULL
             'u' 'pos' '0' values au(i) in [-1, 1), apos(i) in [0.5, 1.5), 0
             'c:EXPR'      element i is EXPR
             '[a, b, ...]' these elements, then zeros
             'set:CODE'    C statements filling the buffer b_
             'h'           a handle from audit_rls_new(3, 2, 2) (m = 3, k = 2,
                           after two updates); 'h0' the same before any;
                           'hpoly' polynomial RLS of order 3, 'hiso' the
                           ISOLATE anomaly policy (audit_rls_new_ex)
             'm'           a simulation model from audit_sim_model_new(0)
                           (6 x 3 geometry), 'mtraj' one of a trajectory,
                           'mnl' the same with the nonlinear truth
A writable pointer given values is an input-output argument: a failed call
must leave it as it was, like an output.

Keys starting with '_' annotate the function:
  _opt, _req     pointer parameters that may / may not be NULL, where the
                 reading of the header comment ("may be NULL", "or NULL")
                 is wrong
  _null_any      NULL is allowed only in some cases: no expectation
  _zero_ok       size parameters for which 0 is valid
  _inf_ok        double parameters (scalar or array) for which +-Inf may
                 be accepted ('name' both signs, 'name+' or 'name-' one):
                 no expectation
  _valid         labels of mutations the header documents as valid
                 ('x=+Inf'): the call must succeed
  _nan_ok        double parameters for which NaN is valid
  _neg_bad       {array: [indices]}: elements that may not be negative (a
                 running count or sum of squares): -1 there must fail
  _ignored       parameters the header says this call does not read: their
                 mutations carry no expectation
  _int           class of an int parameter not in gen_invalid.INT_CLASS
                 (size, ld, enum, nonneg, index, free)
  _intarr        class of a const int array not in gen_invalid.INTARR_CLASS
                 (code, count, flag, free)
  _ret           'bool': the function answers 1/0 (1 for the baseline),
                 mutations must give 0
  _extra         further mutations: [(param, C value, 'ok'|'fail'|'any')]
  _threads       False: not run by the threads suite (process-wide set-up)
  _expect        'any': extreme but finite data, which the call may refuse;
                 it must then leave the outputs untouched, and a success
                 must hold no NaN (no mutations of such a baseline)
  _progress      outputs documented to report how far a call got when it
                 fails on the data (an IGEA_E* status): they may be written
                 then, but not when an argument is invalid (-i)
  _nan_out       outputs documented to hold NaN after a success (a
                 successful call must leave no NaN in any other output)
"""

NAME_DEFAULTS = {
    'm': '6', 'N': '3', 'n': '6',
    'A': 'u', 'S': 'u', 'H': 'u', 'y': 'u', 'dw': 'u',
    'lda': 'm', 'lds': 'm', 'ldc': 'N', 'ldp': 'N', 'ldv': 'N',
    'sigma': 'pos', 'track_sigma': 'pos', 'spec_sigma': 'pos',
    'sigma_inc': '1', 'layout': 'IGEA_COLMAJOR',
    'rcond': '0.0', 'alpha': '0.01',
    'h': 'h',
}

EQ_OPTS = 'set:igea_eqerr_defaults(b_);'
SIM_OPTS = 'set:igea_sim_defaults(b_);'
IMP_OPTS = 'set:igea_impact_defaults(b_);'
INS_OPTS = 'set:igea_inserr_defaults(b_); b_[IGEA_INSERR_OPT_LAT] = 0.7;'
INS_TC_OPTS = ('set:igea_inserr_defaults(b_); b_[IGEA_INSERR_OPT_ACC_TC] = 100.0; '
               'b_[IGEA_INSERR_OPT_GYRO_TC] = 300.0;')
TRIAD_OPTS = ('set:igea_triad_defaults(b_); b_[IGEA_TRIAD_OPT_WINDOW] = 0.5; '
              'b_[IGEA_TRIAD_OPT_INIT] = 3.0;')
# 16 static means in different directions, |m| ~ 9.8 (a triad fit)
TRIAD_MEANS = ('set:for (int k = 0; k < 16; k++) { double a = 0.7 * k, e = 0.4 + 0.37 * k; '
               'b_[3 * k] = 9.8 * cos(a) * sin(e) + 0.01; b_[3 * k + 1] = 9.81 * sin(a) * sin(e) '
               '- 0.02; b_[3 * k + 2] = 9.79 * cos(e) + 0.03 + 1e-4 * sin(3.1 * k); }')
# a record at 10 Hz: 3 s static, then 15 attitudes of 2 s joined by 1 s of motion
TRIAD_RECORD = ('set:for (int i = 0; i < 480; i++) { int k = i < 30 ? 0 : 1 + (i - 30) / 30; '
                'int moving = i >= 30 && (i - 30) % 30 >= 20; double a = 0.7 * k, '
                'e = 0.4 + 0.37 * k, w = moving ? 0.5 : 1e-3; '
                'b_[3 * i] = 9.8 * cos(a) * sin(e) + w * sin(1.3 * i); '
                'b_[3 * i + 1] = 9.81 * sin(a) * sin(e) + w * sin(2.9 * i); '
                'b_[3 * i + 2] = 9.79 * cos(e) + w * sin(5.7 * i); }')
# a gyro record at 10 Hz: 12 static intervals of 2 s joined by 1-s turns of 90 deg
# about x, y, z in turn, and the gravity directions those turns give (a triad gyro fit)
TRIAD_GYRO = ('set:for (int i = 0; i < 350; i++) for (int j = 0; j < 3; j++) b_[3 * i + j] = '
              '(i % 30 >= 20 && j == (i / 30) % 3 ? 1.5707963267948966 : 0.0) '
              '+ 1e-4 * sin(1.3 * i + j);')
TRIAD_GMEANS = ('set:double v[3] = {0, 0, 1}; for (int k = 0; k < 12; k++) { '
                'for (int j = 0; j < 3; j++) b_[3 * k + j] = 9.8 * v[j]; '
                'double x = v[0], y = v[1], z = v[2]; if (k % 3 == 0) { v[1] = z; v[2] = -y; } '
                'else if (k % 3 == 1) { v[0] = -z; v[2] = x; } else { v[0] = y; v[1] = -x; } }')
# the gyro of TRIAD_RECORD: during each 1-s move, the rate turning the gravity
# direction of attitude k into that of k + 1 about their common normal
TRIAD_RECORD_GYRO = ('set:for (int i = 0; i < 480; i++) { int k = i < 30 ? 0 : 1 + (i - 30) / 30; '
                     'int moving = i >= 30 && (i - 30) % 30 >= 20 && k < 15; double u[2][3]; '
                     'for (int q = 0; q < 2; q++) { double a = 0.7 * (k + q), e = 0.4 + 0.37 * (k + q); '
                     'u[q][0] = cos(a) * sin(e); u[q][1] = sin(a) * sin(e); u[q][2] = cos(e); } '
                     'double c[3] = {u[0][1] * u[1][2] - u[0][2] * u[1][1], '
                     'u[0][2] * u[1][0] - u[0][0] * u[1][2], u[0][0] * u[1][1] - u[0][1] * u[1][0]}; '
                     'double sn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), '
                     'cs = u[0][0] * u[1][0] + u[0][1] * u[1][1] + u[0][2] * u[1][2], '
                     'phi = atan2(sn, cs); for (int j = 0; j < 3; j++) b_[3 * i + j] = '
                     '(moving ? -phi * c[j] / sn : 0.0) + 1e-4 * sin(1.7 * i + j); }')
TRAJ = 'set:igea_sim_trajectory(IGEA_ENVFUN_STRAPDOWN, 10.0, 10.0, 101, b_, 101);'
THETA30 = 'c:30.0 * (double)i'
YA_DUAL = 'c:asind(30.0 * (double)i) + 1e-4 * au(i)'
# two tumble planes of 8 equispaced positions each (the IEEE Std 1293 model)
IEEE_THETA = 'c:45.0 * (double)(i % 8) + (i < 8 ? 0.0 : 10.0)'
IEEE_E = 'c:2.5 * asind(45.0 * (double)(i % 8) + (i < 8 ? 0.0 : 10.0)) + 1e-4 * au(i)'
YB_DUAL = 'c:acosd(30.0 * (double)i) + 1e-4 * au(i + 500)'

NAV_SITE = 'set:igea_nav_site(0.7, 1.7, 100.0, 0.5, b_);'
NAV_STATE = ('set:{ double s_[IGEA_NAV_SITE_LEN]; igea_nav_site(0.7, 1.7, 100.0, 0.5, s_); '
             'igea_nav_init(IGEA_ENVFUN_STRAPDOWN, s_, IGEA_NAV_GRAVITY_J2, 0, 0.0, NULL, NULL, '
             'NULL, b_); }')
# 101 telemetry records at 100 Hz (t dv3 dth3), 5 tracking epochs (t r3 v3 sigma)
DW_TEL = ('set:for (int k = 0; k < 101; k++) { b_[k] = 0.01 * k; for (int c = 1; c < 7; c++) '
          'b_[k + 101 * c] = k ? (c < 4 ? 0.2 : 1e-4) : 0.0; }')
DW_TRK = ('set:for (int e = 0; e < 5; e++) { b_[e] = 0.2 * (e + 1); for (int c = 1; c < 7; c++) '
          'b_[e + 5 * c] = 0.1 * c * (e + 1); b_[e + 35] = 0.01; }')
# the same 5 epochs with a 6 x 6 position-velocity covariance (28 columns: its upper
# triangle row by row, 1 on the diagonal, 0.1 off it)
DW_TRK28 = ('set:for (int e = 0; e < 5; e++) { b_[e] = 0.2 * (e + 1); for (int c = 1; c < 7; c++) '
            'b_[e + 5 * c] = 0.1 * c * (e + 1); for (int i = 0, c = 7; i < 6; i++) '
            'for (int j = i; j < 6; j++, c++) b_[e + 5 * c] = i == j ? 1.0 : 0.1; }')

BASE = {
    # ---- common
    'igea_strerror': dict(status='IGEA_ENOMEM', _int=dict(status='free'),
                          _extra=[('status', 'INT_MIN', 'ok'), ('status', '12345', 'ok'),
                                  ('status', '-1', 'ok'), ('status', '0', 'ok')]),
    'igea_status_class': dict(status='IGEA_ESINGULAR', _int=dict(status='free'),
                              _extra=[('status', 'INT_MIN', 'ok'), ('status', '12345', 'ok'),
                                      ('status', '-1', 'ok'), ('status', '0', 'ok')]),
    'igea_init': dict(_threads=False),
    'igea_opt_name': dict(module='IGEA_MODULE_EQERR', slot='0',
                          _int=dict(module='free', slot='free'),
                          _extra=[('module', '12345', 'ok'), ('slot', '-1', 'ok'),
                                  ('slot', 'INT_MIN', 'ok'), ('slot', '12345', 'ok')]),
    'igea_choice_name': dict(kind='IGEA_CHOICE_EQERR_ROUTE', code='IGEA_EQERR_ROUTE_SVD',
                             _int=dict(kind='free', code='free'),
                             _extra=[('kind', '0', 'ok'), ('kind', 'INT_MIN', 'ok'),
                                     ('code', '-1', 'ok'), ('code', 'INT_MAX', 'ok')]),
    'igea_choice_code': dict(kind='IGEA_CHOICE_STABILITY_NOISE', name='set:memcpy(b_, "ffm", 4);',
                             _intarr=dict(name='free'), _int=dict(kind='enum'), _req=['name', 'code']),
    'igea_choice_codes': dict(kind='IGEA_CHOICE_STABILITY_NOISE', len='6', _int=dict(kind='enum', len='size'),
                              _zero_ok=['len'], _req=['codes']),
    # ---- stats
    'igea_stats_normal_cdf': dict(x='0.5', _valid=['x=+Inf', 'x=-Inf']),
    'igea_stats_normal_quantile': dict(p='0.3'),
    'igea_stats_normal_sf': dict(x='0.5', _valid=['x=+Inf', 'x=-Inf']),
    'igea_stats_t_sf': dict(t='1.5', dof='7.0', _valid=['t=+Inf', 't=-Inf']),
    'igea_stats_t_quantile': dict(p='0.975', dof='7.0'),
    'igea_stats_f_sf': dict(f='1.5', d1='3.0', d2='20.0', _valid=['f=+Inf']),
    'igea_stats_chi2_cdf': dict(x='2.0', dof='3.0', _valid=['x=+Inf']),
    'igea_stats_chi2_sf': dict(x='2.0', dof='3.0', _valid=['x=+Inf']),
    'igea_stats_chi2_quantile': dict(p='0.3', dof='3.0'),
    'igea_stats_chi2_upper': dict(alpha='0.01', dof='11.0'),
    'igea_stats_accuracy_test': dict(equiv_err='u', **{'lambda': 'c:20.0 + (double)i'},
                                     lambda_test='10.0', z_crit='2.58'),
    'igea_stats_pool': dict(nflights='3', chi2='[2.0, 3.0, 1.5]', dof='[2, 3, 2]',
                            n_reject='[0, 0, 0]', unit_id='[1, 2, 3]'),
    'igea_stats_union_size': dict(n='3', a='2.5', b='11.0', _inf_ok=['a+', 'b+'],
                                  _valid=['a=+Inf', 'b=+Inf']),
    'igea_stats_verdict_thresholds': dict(rule='IGEA_STATS_VERDICT_EXACT', n='3'),
    # ---- normal
    'igea_normal_accumulate': dict(lda='N', A='0', b='0', wtw='0', _zero_ok=['m'],
                                   _neg_bad={'wtw': [0, 1]}),
    'igea_normal_accumulate_threads': dict(lda='N', A='0', b='0', wtw='0', nthreads='2',
                                           _zero_ok=['m'], _opt=['spec_sigma'],
                                           _neg_bad={'wtw': [0, 1]}),
    'igea_normal_qr_accumulate': dict(R='0', ldr='N + 1', rows='0', _zero_ok=['m'],
                                      _opt=['spec_sigma'], _neg_bad={'rows': [0]}),
    # ---- eqerr
    'igea_eqerr_check_opts': dict(opts=EQ_OPTS, _nan_ok=['opts'], _inf_ok=['opts'],
                                  _req=['opts']),
    'igea_eqerr_solve': dict(A='set:audit_spd(b_, 3, 3, 100.0);', lda='N', b='u', opts=EQ_OPTS),
    'igea_eqerr_solve_qr': dict(R='set:audit_upper(b_, 4, 4, 10.0);', ldr='N + 1', rows='20.0',
                                opts=EQ_OPTS),
    'igea_eqerr_run': dict(m='12', track_sigma='c:0.05', opts=EQ_OPTS, _req=['S', 'dw', 'z']),
    'igea_eqerr_run_layout': dict(m='12', track_sigma='c:0.05', opts=EQ_OPTS,
                                  _req=['S', 'dw', 'z']),
    'igea_eqerr_coef': dict(P='u', equiv_err='u', n_test='2', _int=dict(n_test='nonneg'),
                            _req=['coef']),
    'igea_eqerr_residual': dict(coef='u', row0='0', axis_ss='0', _zero_ok=['m']),
    'igea_eqerr_residual_threads': dict(coef='u', row0='0', axis_ss='0', nthreads='2',
                                        _zero_ok=['m']),
    'igea_eqerr_pool': dict(nflights='3', chi2='[2.0, 3.0, 1.5]', dof='[2, 3, 2]', z='u',
                            unit_id='[1, 2, 3]', opts=EQ_OPTS, _req=['z'], _opt=['reject']),
    'igea_eqerr_limits': dict(n='3', **{'lambda': 'c:20.0 + (double)i'}, z_crit='2.58'),
    'igea_eqerr_axis_rms': dict(axis_ss='[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]'),
    'igea_eqerr_axis_sums': dict(row0='1', sums='0', _zero_ok=['m'], _neg_bad={'sums': [0]}),
    'igea_eqerr_accumulate': dict(lda='N', A='0', b='0', wtw='0', nthreads='2', row0='1', sums='0',
                                  _zero_ok=['m'], _opt=['spec_sigma'],
                                  _neg_bad={'wtw': [0, 1], 'sums': [0]}),
    'igea_eqerr_residual_mean': dict(sums='c:(i % 5 == 0) ? 4.0 : au(i)', coef='u'),
    'igea_eqerr_diag_add': dict(m='6', residual='u', row0='2',
                                state='set:for (int a = 0; a < 3; a++) igea_stats_diag_init(2, 0.1, b_ + a * IGEA_STATS_DIAG_STATE_LEN);',
                                _zero_ok=['m']),
    'igea_eqerr_diag': dict(m='30', residual='u', lags='3', _int={'lags': 'size'}),
    'igea_stats_diag_init': dict(lags='3', center='0.1', _int={'lags': 'size'}),
    'igea_stats_diag_add': dict(n='6', x='u', incx='1',
                                state='set:igea_stats_diag_init(2, 0.1, b_);', _zero_ok=['n'],
                                _int={'incx': 'size'}),
    'igea_stats_diag_result': dict(state='set:igea_stats_diag_init(1, 0.0, b_); { double v[5] = {1, -2, 3, 0.5, -1}; igea_stats_diag_add(5, v, 1, b_); }'),
    'igea_eqerr_components': dict(P='u', ldp='N', ncomp='2', _int={'ncomp': 'size'},
                                  _zero_ok=['ncomp']),
    'igea_stats_whiteness': dict(n='10', x='u', incx='1', lags='3',
                                 _int={'lags': 'size', 'incx': 'size'}),
    # ---- regress
    'igea_regress_ebr': dict(m='8', rule='IGEA_REGRESS_EBR_SC', lam_floor='0.0', _req=['x']),
    'igea_regress_ls': dict(_req=['x'], _inf_ok=['rcond-']),
    'igea_regress_ls_diag': dict(m='8', alpha='0.05', _req=['x', 'sd', 'diag'], _inf_ok=['rcond-'],
                                 _opt=['tvalues', 'pvalues', 'ci_lower', 'ci_upper', 'leverage', 'cooks_d']),
    'igea_regress_rank_info': dict(_inf_ok=['rcond-']),
    'igea_regress_sd': dict(cov='set:audit_spd(b_, 3, 3, 1.0);', ldc='N'),
    'igea_regress_ls_ex': dict(flags='0', _int=dict(flags='enum'), _req=['x', 'info'], _inf_ok=['rcond-']),
    'igea_regress_ls_full': dict(m='8', flags='0', alpha='0.05', _int=dict(flags='enum'),
                                 _req=['x', 'sigma2', 'info', 'diag'], _inf_ok=['rcond-'],
                                 _opt=['cov', 'sd', 'residual', 'tvalues', 'pvalues', 'ci_lower',
                                       'ci_upper', 'leverage', 'cooks_d']),
    'igea_regress_ridge': dict(rule='IGEA_REGRESS_RIDGE_FIXED', k='0.1', _req=['A', 'x', 'y']),
    'igea_regress_ridge_trace': dict(nk='3', k='[0.0, 0.1, 1.0]', ldx='N', _req=['k']),
    'igea_regress_pce': dict(ncomp='0', eig_min='0.01', _zero_ok=['ncomp']),
    'igea_regress_ridge_ex': dict(rule='IGEA_REGRESS_RIDGE_FIXED', k='0.1', _req=['A', 'x', 'y', 'info']),
    'igea_regress_pce_ex': dict(ncomp='0', eig_min='0.01', _zero_ok=['ncomp'], _req=['x', 'info']),
    'igea_regress_bayes': dict(prior_mean='u', prior_cov='set:audit_spd(b_, 3, 3, 1.0);',
                               _req=['A', 'x', 'y']),
    'igea_regress_collinearity': dict(_inf_ok=['rcond-']),
    # ---- accel
    'igea_accel_schedule': dict(n='8', start_deg='0.0'),
    'igea_accel_merge': dict(nrows='8', angle_deg='c:45.0 * (double)i', ya='u', yb='u',
                             tol_deg='1.0', _null_any=['yb', 'yb_mean']),
    'igea_accel_to_g': dict(raw='u', scale='2.5'),
    'igea_accel_observe': dict(model='IGEA_ACCEL_DUAL', n='8', theta_deg=THETA30,
                               ya=YA_DUAL, yb=YB_DUAL, _req=['yb']),
    'igea_accel_design': dict(model='IGEA_ACCEL_DUAL', n='12', theta_deg=THETA30, lda='n'),
    'igea_accel_combinations': dict(model='IGEA_ACCEL_DUAL', ldc='9'),
    'igea_accel_analyze': dict(model='IGEA_ACCEL_DUAL', n='12', theta_deg=THETA30, ldn='9'),
    'igea_accel_fit': dict(model='IGEA_ACCEL_DUAL', method='IGEA_ACCEL_EBR', n='12',
                           theta_deg=THETA30, ya=YA_DUAL, yb=YB_DUAL, prior_scale='pos',
                           rule='IGEA_REGRESS_EBR_SC', lam_floor='0.0', _req=['yb']),
    'igea_accel_refine': dict(n='12', theta_deg=THETA30, ya=YA_DUAL, yb=YB_DUAL, coef0='0',
                              max_iter='50', tol='1e-9'),
    'igea_accel_coef_name': dict(model='IGEA_ACCEL_DUAL', axis='IGEA_ACCEL_AXIS_OA', j='7',
                                 _int=dict(model='free', axis='free', j='free'),
                                 _extra=[('model', '12345', 'ok'), ('axis', '-1', 'ok'),
                                         ('j', '9', 'ok'), ('j', 'INT_MIN', 'ok')]),
    'igea_accel_comb_name': dict(model='IGEA_ACCEL_DUAL', axis='IGEA_ACCEL_AXIS_PA', k='4',
                                 _int=dict(model='free', axis='free', k='free'),
                                 _extra=[('model', '-1', 'ok'), ('axis', '2', 'ok'),
                                         ('k', '7', 'ok'), ('k', '-1', 'ok')]),
    'igea_accel_coef_unit': dict(model='IGEA_ACCEL_SINGLE', j='2',
                                 _int=dict(model='free', j='free'),
                                 _extra=[('model', '2', 'ok'), ('j', '5', 'ok'), ('j', '-1', 'ok')]),
    'igea_accel_combine': dict(model='IGEA_ACCEL_DUAL', coef='c:1e-4 * au(i)'),
    'igea_accel_simulate': dict(n='12', theta_deg=THETA30, truth='c:1e-4 * au(i)',
                                head_sd='1e-6', noise_sd='1e-5', seed='1'),
    'igea_redund_group': dict(nsens='8', ngroup='4',
                              axes='set:for (int i = 0; i < 8; i++) { int k = i < 4 ? 0 : (i < 6 ? 1 : 2); '
                                   'for (int j = 0; j < 3; j++) b_[3 * i + j] = j == k ? 1.0 + 1e-3 * i '
                                   ': 1e-3 * (double)(i - j); }',
                              sigma='pos', member='[0, 4, 6, 1, 5, 7, 2, 4, 6, 3, 5, 7]', y='u',
                              fusion='IGEA_REDUND_GROUP_WEIGHTED', _int=dict(fusion='enum')),
    'igea_redund_stability': dict(nsamp='400', nsens='4', ldy='nsamp', fs='10.0', block='5.0',
                                  channel='[0, 0, 1, -1]', nchan='2', weighted='1',
                                  _int=dict(weighted='enum', nchan='size'), _opt=['fused'],
                                  _intarr=dict(channel='free')),
    # ---- inserr
    'igea_inserr_check_opts': dict(opts=INS_OPTS, _nan_ok=['opts'], _inf_ok=['opts'],
                                   _req=['opts']),
    'igea_inserr_matrix': dict(opts=INS_OPTS),
    'igea_inserr_response': dict(opts=INS_OPTS, x0='[0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0, '
                                 '0.0, 1e-4, -2e-4, 0.0, 0.0, 5e-8, 0.0]', duration='600.0',
                                 n='6'),
    'igea_inserr_covariance': dict(opts=INS_OPTS, P0='0', q='c:1e-9 * (1.0 + (double)i)',
                                   duration='600.0', n='6'),
    'igea_inserr_noise_covariance': dict(opts='set:igea_inserr_defaults(b_); b_[IGEA_INSERR_OPT_LAT] '
                                         '= 0.7; b_[IGEA_INSERR_OPT_ACC_TC] = 100.0; b_[IGEA_INSERR_OPT_GYRO_TC] = 300.0;', P0='0',
                                         acc='c:1e-4 * (1.0 + (double)i)',
                                         gyro='c:1e-7 * (1.0 + (double)i)', duration='600.0',
                                         n='6'),
    'igea_inserr_li_response': dict(system='IGEA_ENVFUN_STRAPDOWN', site=NAV_SITE,
                                    gravity='IGEA_NAV_GRAVITY_J2', nsamp='101', tel=DW_TEL,
                                    ldtel='nsamp', q0='[0.9, 0.1, 0.3, 0.2]', r0='u', v0='u',
                                    x0='c:1e-3 * au(i)', nepochs='3',
                                    epochs='c:0.5 * (double)i', _int=dict(gravity='enum')),
    'igea_inserr_li_covariance': dict(system='IGEA_ENVFUN_STRAPDOWN', site=NAV_SITE,
                                      gravity='IGEA_NAV_GRAVITY_J2', nsamp='101', tel=DW_TEL,
                                      ldtel='nsamp', q0='[0.9, 0.1, 0.3, 0.2]', r0='u', v0='u',
                                      P0='0', q='c:1e-9 * (1.0 + (double)i)', nepochs='3',
                                      epochs='c:0.5 * (double)i', _int=dict(gravity='enum')),
    'igea_inserr_li_response_opts': dict(system='IGEA_ENVFUN_STRAPDOWN', site=NAV_SITE,
                                         gravity='IGEA_NAV_GRAVITY_J2', opts=INS_TC_OPTS,
                                         nsamp='101', tel=DW_TEL, ldtel='nsamp',
                                         q0='[0.9, 0.1, 0.3, 0.2]', r0='u', v0='u',
                                         x0='c:1e-3 * au(i)', nepochs='3',
                                         epochs='c:0.5 * (double)i', _int=dict(gravity='enum')),
    'igea_inserr_li_covariance_opts': dict(system='IGEA_ENVFUN_STRAPDOWN', site=NAV_SITE,
                                           gravity='IGEA_NAV_GRAVITY_J2', opts=INS_TC_OPTS,
                                           nsamp='101', tel=DW_TEL, ldtel='nsamp',
                                           q0='[0.9, 0.1, 0.3, 0.2]', r0='u', v0='u', P0='0',
                                           q='c:1e-9 * (1.0 + (double)i)', nepochs='3',
                                           epochs='c:0.5 * (double)i', _int=dict(gravity='enum')),
    'igea_inserr_li_noise_covariance': dict(system='IGEA_ENVFUN_STRAPDOWN', site=NAV_SITE,
                                            gravity='IGEA_NAV_GRAVITY_J2', opts=INS_TC_OPTS,
                                            nsamp='101', tel=DW_TEL, ldtel='nsamp',
                                            q0='[0.9, 0.1, 0.3, 0.2]', r0='u', v0='u', P0='0',
                                            acc='c:1e-4 * (1.0 + (double)i)',
                                            gyro='c:1e-7 * (1.0 + (double)i)', nepochs='3',
                                            epochs='c:0.5 * (double)i', _int=dict(gravity='enum')),
    'igea_accel_apply': dict(model='IGEA_ACCEL_DUAL', n='12', raw_a=YA_DUAL, raw_b=YB_DUAL,
                             scale_a='1.0', scale_b='1.0', coef='c:1e-4 * au(i)',
                             cross='NULL', _ignored=['cross'], _req=['raw_b']),
    'igea_accel_hysteresis': dict(nrows='16', angle_deg='c:90.0 * (double)(i % 4)',
                                  dir='c:i < 8 ? 1 : -1', y='u', tol_deg='1.0',
                                  _intarr=dict(dir='free'), _null_any=['dir']),
    'igea_accel_joint': dict(n='12', theta_deg=THETA30, ya=YA_DUAL, yb=YB_DUAL, ldc='10',
                             _int=dict(ldc='ld')),
    'igea_accel_ieee_fit': dict(method='IGEA_ACCEL_LS', n='16', theta_deg=IEEE_THETA,
                                plane='c:i < 8 ? 0 : 1', e=IEEE_E, ldc='8',
                                _int=dict(ldc='ld'), _intarr=dict(plane='code')),
    'igea_accel_history': dict(m='6', p='2', b='c:1.0 + (double)(i % 2) + 0.3 * au(i)',
                               ldb='2', ldv='2', max_iter='100000', tol='1e-8', ldc='2',
                               V='set:for (int i = 0; i < 6; i++) { b_[4 * i] = 0.1; '
                                 'b_[4 * i + 1] = b_[4 * i + 2] = 0.01; '
                                 'b_[4 * i + 3] = 0.2 + 0.01 * i; }',
                               _int=dict(ldb='ld', ldv='ld', ldc='ld')),
    'igea_accel_history_full': dict(m='6', p='2', b='c:1.0 + (double)(i % 2) + 0.3 * au(i)',
                                    ldb='2', ldv='2', max_iter='100000', tol='1e-8', lds='2',
                                    ldc='2',
                                    V='set:for (int i = 0; i < 6; i++) { b_[4 * i] = 0.1; '
                                      'b_[4 * i + 1] = b_[4 * i + 2] = 0.01; '
                                      'b_[4 * i + 3] = 0.2 + 0.01 * i; }',
                                    _int=dict(ldb='ld', ldv='ld', lds='ld', ldc='ld')),
    'igea_accel_fit_prior': dict(model='IGEA_ACCEL_DUAL', n='12', theta_deg=THETA30, ya=YA_DUAL,
                                 yb=YB_DUAL, prior_mean='c:1e-4 * au(i)', ldp='9', ldc='9',
                                 prior_cov='set:for (int i = 0; i < 81; i++) '
                                           'b_[i] = i % 10 == 0 ? 1e-8 : 0.0;',
                                 _int=dict(ldp='ld', ldc='ld'), _req=['yb']),
    'igea_accel_history_information': dict(
        m='6', p='2', b='c:1.0 + (double)(i % 2) + 0.3 * au(i)', ldb='2', ldv='2',
        V='set:for (int i = 0; i < 6; i++) { b_[4 * i] = 0.1; b_[4 * i + 1] = b_[4 * i + 2] = 0.01; '
          'b_[4 * i + 3] = 0.2 + 0.01 * i; }',
        sigma_u='[0.3, 0.05, 0.05, 0.2]', lds='2', full='1', ldi='3',
        _int=dict(ldb='ld', ldv='ld', lds='ld', ldi='ld', full='enum')),
    'igea_accel_fit_history': dict(
        model='IGEA_ACCEL_DUAL', n='12', theta_deg=THETA30, ya=YA_DUAL, yb=YB_DUAL, m='6',
        b='c:1e-4 * au(i)', ldb='9', ldv='9',
        V='set:for (int i = 0; i < 6 * 81; i++) b_[i] = i % 10 == 0 ? 1e-10 : 0.0;',
        sigma_u='set:for (int i = 0; i < 81; i++) b_[i] = i % 10 == 0 ? 1e-9 : 0.0;', lds='9',
        full='0', alpha='0.05', ldc='9',
        _int=dict(ldb='ld', ldv='ld', lds='ld', ldc='ld', full='enum'), _req=['yb']),
    'igea_accel_criterion': dict(model='IGEA_ACCEL_DUAL', method='IGEA_ACCEL_JOINT', n='12',
                                 theta_deg=THETA30, plane='NULL', head_ratio='4.85',
                                 _ignored=['plane']),
    # ---- impact
    'igea_impact_check_opts': dict(opts=IMP_OPTS, _nan_ok=['opts'], _inf_ok=['opts'],
                                   _req=['opts']),
    'igea_impact_point': dict(model='IGEA_IMPACT_KEPLER', opts=IMP_OPTS,
                              r0='[6471008.8, 0.0, 0.0]', v0='[2500.0, 4330.0, 500.0]',
                              ldj='IGEA_IMPACT_JAC_ROWS', _int=dict(ldj='ld'),
                              _req=['r0', 'v0', 'rf']),
    'igea_impact_axes': dict(rf='[6371008.8, 0.0, 0.0]', vf='[-1000.0, 3000.0, 500.0]'),
    'igea_impact_miss_jacobian': dict(jac='u', ldj='IGEA_IMPACT_JAC_ROWS',
                                      rf='[6371008.8, 0.0, 0.0]', vf='[-1000.0, 3000.0, 500.0]',
                                      ldg='2', _int=dict(ldj='ld', ldg='ld')),
    'igea_impact_budget': dict(n='3', G='u', ldg='2', E='u', lde='6',
                               _int=dict(ldg='ld', lde='ld'), _req=['miss']),
    'igea_impact_circle_prob': dict(cov='[4.0, 1.0, 1.0, 2.0]', r='1.5'),
    'igea_impact_cep': dict(cov='[4.0, 1.0, 1.0, 2.0]', prob='0.5'),
    'igea_impact_cep_approx': dict(cov='[4.0, 1.0, 1.0, 2.0]', rule='IGEA_IMPACT_CEP_SUM'),
    'igea_impact_circle_prob_offset': dict(cov='[4.0, 1.0, 1.0, 2.0]', mean='[1.0, -0.5]',
                                           r='1.5'),
    'igea_impact_cep_offset': dict(cov='[4.0, 1.0, 1.0, 2.0]', mean='[1.0, -0.5]', prob='0.5'),
    'igea_impact_component_miss': dict(N='3', n='2', G='u', ldg='2', E='u', lde='6', P='u',
                                       ldp='N', equiv='u'),
    'igea_impact_burnout': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                                ldt='nsamp', nterms='3', terms='[0, 15, 24]', axes='NULL',
                                spec='pos', site=NAV_SITE, tb='7.35', lde='6',
                                _opt=['spec', 'axes'], _null_any=['E'], _zero_ok=['nterms'],
                                _int=dict(nterms='nonneg', lde='ld')),
    # ---- triad
    'igea_triad_check_opts': dict(opts=TRIAD_OPTS, _nan_ok=['opts'], _inf_ok=['opts'],
                                  _req=['opts']),
    'igea_triad_static': dict(layout='IGEA_ROWMAJOR', n='60', acc='u', lda='3', fs='10.0',
                              window='0.5', threshold='1.0', min_static='0.5', maxint='4',
                              _int=dict(maxint='size'), _zero_ok=['maxint'],
                              _null_any=['start', 'end']),
    'igea_triad_fit': dict(nint='16', means=TRIAD_MEANS, g='9.80665', theta0='NULL',
                           max_iter='200', ldc='9', _nan_out=['info'], _int=dict(nint='size')),
    'igea_triad_calibrate': dict(layout='IGEA_ROWMAJOR', n='480', acc=TRIAD_RECORD, lda='3',
                                 fs='10.0', opts=TRIAD_OPTS, ldc='9'),
    'igea_triad_apply': dict(layout='IGEA_ROWMAJOR', n='5', raw='u', ldr='3',
                             theta='[0.01, 0.02, 0.03, 1.0, 1.01, 0.99, 0.001, 0.002, 0.003]',
                             ldc='3'),
    'igea_triad_gyro_fit': dict(layout='IGEA_ROWMAJOR', n='350', gyro=TRIAD_GYRO, ldg='3',
                                fs='10.0', nint='12', start='c:30 * i', end='c:30 * i + 20',
                                means=TRIAD_GMEANS,
                                theta_a='[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]',
                                cov_a='c:i % 10 == 0 ? 1e-8 : 0.0', ldca='9', max_iter='200',
                                ldc='12', _int=dict(nint='size', ldg='ld', ldca='ld'),
                                _intarr=dict(start='code', end='code')),
    'igea_triad_gyro_fit_earth': dict(layout='IGEA_ROWMAJOR', n='350', gyro=TRIAD_GYRO, ldg='3',
                                      fs='10.0', nint='12', start='c:30 * i',
                                      end='c:30 * i + 20', means=TRIAD_GMEANS,
                                      theta_a='[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]',
                                      cov_a='c:i % 10 == 0 ? 1e-8 : 0.0', ldca='9',
                                      max_iter='200', earth_rate='7.292115e-5',
                                      lat_deg='45.0', ldc='12',
                                      _int=dict(nint='size', ldg='ld', ldca='ld'),
                                      _intarr=dict(start='code', end='code')),
    'igea_triad_calibrate_imu': dict(layout='IGEA_ROWMAJOR', n='480', acc=TRIAD_RECORD, lda='3',
                                     gyro=TRIAD_RECORD_GYRO, ldg='3', fs='10.0', opts=TRIAD_OPTS,
                                     ldca='9', ldcg='12', _int=dict(ldg='ld', ldca='ld',
                                                                    ldcg='ld')),
    'igea_triad_gyro_apply': dict(layout='IGEA_ROWMAJOR', n='5', raw='u', ldr='3',
                                  theta='[0.01, 0.02, 0.03, 1.0, 1.01, 0.99, 0.001, 0.002, '
                                        '0.003, -0.001, -0.002, 0.0015]', ldc='3'),
    # ---- envfun
    'igea_envfun_term_valid': dict(system='IGEA_ENVFUN_STRAPDOWN', term='IGEA_ENVFUN_TERM_ACC_BIAS_X',
                                   _ret='bool'),
    'igea_envfun_term_name': dict(term='IGEA_ENVFUN_TERM_GYRO_G_X', _int=dict(term='free'),
                                  _extra=[('term', '-1', 'ok'), ('term', 'INT_MIN', 'ok'),
                                          ('term', 'IGEA_ENVFUN_TERM_COUNT', 'ok')]),
    'igea_envfun_term_unit': dict(term='IGEA_ENVFUN_TERM_GYRO_G_X', _int=dict(term='free'),
                                  _extra=[('term', '-1', 'ok'), ('term', 'INT_MIN', 'ok'),
                                          ('term', 'IGEA_ENVFUN_TERM_COUNT', 'ok')]),
    # code 0 (acc_bias_x) reads as the success status 0
    'igea_envfun_term_code': dict(system='IGEA_ENVFUN_STRAPDOWN',
                                  name='set:memcpy(b_, "acc_bias_x", 11);', _intarr=dict(name='free'),
                                  _req=['name']),
    'igea_envfun_default_spec': dict(system='IGEA_ENVFUN_PLATFORM', term='IGEA_ENVFUN_TERM_GYRO_GS_X',
                                     _int=dict(term='enum'),
                                     _extra=[('term', 'IGEA_ENVFUN_TERM_ATT0_X', 'fail'),
                                             ('term', '-1', 'fail')]),
    'igea_envfun_default_terms': dict(system='IGEA_ENVFUN_PLATFORM', cap='IGEA_ENVFUN_DEFAULT_TERMS',
                                      _int=dict(cap='size'),
                                      _extra=[('cap', 'IGEA_ENVFUN_DEFAULT_TERMS - 1', 'fail')]),
    'igea_envfun_compute': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                                ldt='nsamp', nterms='3', terms='[0, 3, 15]', axes='NULL',
                                nepochs='5', epochs='c:2.0 * (double)i', spec='pos',
                                output='IGEA_ENVFUN_VELOCITY', lds='3 * nepochs', _opt=['spec']),
    # ---- envfun: the extended catalogue, user terms, the truth model
    'igea_envfun_term_formula': dict(term='IGEA_ENVFUN_TERM_ACC_CUBE_X', _int=dict(term='free'),
                                     _extra=[('term', '-1', 'ok'), ('term', 'INT_MIN', 'ok'),
                                             ('term', 'IGEA_ENVFUN_TERM_COUNT', 'ok'),
                                             ('term', 'IGEA_ENVFUN_TERM_END', 'ok')]),
    'igea_envfun_all_terms': dict(system='IGEA_ENVFUN_PLATFORM', cap='IGEA_ENVFUN_TERM_END',
                                  _int=dict(cap='size'), _extra=[('cap', '73', 'fail')]),
    'igea_envfun_compute_user': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                                     ldt='nsamp', nterms='3', terms='[0, 3, 84]', axes='NULL',
                                     nuser='2', user_kind='[0, 1]', user='u', ldu='nsamp',
                                     nepochs='5', epochs='c:2.0 * (double)i', spec='pos',
                                     output='IGEA_ENVFUN_VELOCITY', lds='3 * nepochs',
                                     _opt=['spec'], _req=['terms', 'user_kind', 'user'],
                                     _zero_ok=['nterms', 'nuser'],
                                     _int=dict(nterms='nonneg', nuser='nonneg'),
                                     _intarr=dict(user_kind='code')),
    'igea_envfun_compute_site': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                                     ldt='nsamp', nterms='3', terms='[0, 82, 83]', axes='NULL',
                                     nuser='2', user_kind='[0, 1]', user='u', ldu='nsamp',
                                     nepochs='5', epochs='c:2.0 * (double)i', spec='pos',
                                     output='IGEA_ENVFUN_VELOCITY_G', site=NAV_SITE,
                                     lds='3 * nepochs',
                                     _opt=['spec', 'site'], _req=['terms', 'user_kind', 'user'],
                                     _zero_ok=['nterms', 'nuser'],
                                     _int=dict(nterms='nonneg', nuser='nonneg'),
                                     _intarr=dict(user_kind='code')),
    'igea_envfun_nonlinear': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                                  ldt='nsamp', nerr='IGEA_ENVFUN_TERM_END',
                                  err='set:for (long i = 0; i < AUDIT_NB; i++) { b_[i] = 0; }'
                                  ' b_[0] = 1e-3; b_[15] = 1e-6; b_[40] = 1e-8; b_[82] = 5.0;'
                                  ' b_[84] = 0.1; b_[87] = 0.01;',
                                  axes='NULL', nepochs='5', epochs='c:2.0 * (double)i',
                                  _int=dict(nerr='size'),
                                  _extra=[('nerr', 'IGEA_ENVFUN_TERM_COUNT - 1', 'fail'),
                                          ('nerr', 'IGEA_ENVFUN_TERM_END + 1', 'fail')]),
    # ---- nav, dw
    'igea_nav_geodetic_to_ecef': dict(lat='0.7', lon='1.7', h='100.0'),
    'igea_nav_ecef_to_geodetic': dict(r='[4.0e6, 3.0e6, 3.5e6]'),
    'igea_nav_site': dict(lat='0.7', lon='1.7', h='100.0', azimuth='0.5'),
    'igea_nav_transform': dict(site=NAV_SITE, **{'from': 'IGEA_NAV_LE'}, to='IGEA_NAV_LI',
                               t='10.0', r_in='u', v_in='u', _int={'from': 'enum', 'to': 'enum'}),
    'igea_nav_rotation': dict(site=NAV_SITE, **{'from': 'IGEA_NAV_ECEF'}, to='IGEA_NAV_LI',
                              t='10.0', _int={'from': 'enum', 'to': 'enum'}),
    'igea_nav_gravity': dict(model='IGEA_NAV_GRAVITY_J2', r='[4.0e6, 3.0e6, 3.5e6]'),
    'igea_nav_gravity_li': dict(site=NAV_SITE, model='IGEA_NAV_GRAVITY_J2', r_li='u'),
    'igea_nav_init': dict(system='IGEA_ENVFUN_STRAPDOWN', site=NAV_SITE,
                          gravity='IGEA_NAV_GRAVITY_J2', flags='0', t0='0.0',
                          q0='[0.9, 0.1, 0.3, 0.2]', r0='u', v0='u',
                          _int=dict(gravity='enum', flags='enum')),
    'igea_nav_step': dict(state=NAV_STATE, t='0.01', dv='u', dth='u'),
    'igea_dw_summary': dict(ntrk='4', _int=dict(ntrk='size'), _opt=['cov', 'sigma', 'max_abs', 'rms'], dw='u', cov='c:(i % 6 == 0 || i % 6 == 3 || i % 6 == 5) ? 1.0 + 0.1 * (double)i : 0.01'),

    'igea_dw_compute': dict(site=NAV_SITE, system='IGEA_ENVFUN_STRAPDOWN', kind='IGEA_DW_APPARENT',
                            q0='[1.0, 0.0, 0.0, 0.0]', time_offset='0.0', ntel='101', tel=DW_TEL, ldtel='ntel', tel_cols='7',
                            frame='IGEA_NAV_LE', ntrk='5', trk=DW_TRK, ldtrk='ntrk', trk_cols='8',
                            _int=dict(ntel='size', ntrk='size', tel_cols='enum', trk_cols='enum',
                                      frame='enum'),
                            _opt=['dw_dtau'], _progress=['bad']),
    'igea_dw_compute_k': dict(site=NAV_SITE, system='IGEA_ENVFUN_STRAPDOWN', kind='IGEA_DW_APPARENT',
                              q0='[1.0, 0.0, 0.0, 0.0]', time_offset='0.0', ntel='101', tel=DW_TEL,
                              ldtel='ntel', tel_cols='7', frame='IGEA_NAV_LE', ntrk='5', trk=DW_TRK28,
                              ldtrk='ntrk', trk_cols='28',
                              _int=dict(ntel='size', ntrk='size', tel_cols='enum', trk_cols='enum',
                                        frame='enum'),
                              _opt=['dw_dtau', 'xcov', 'q0'], _null_any=['cov'],
                              _progress=['bad']),
    # ---- sim
    'igea_sim_trajectory_length': dict(duration='10.0', rate='10.0'),
    'igea_sim_trajectory': dict(system='IGEA_ENVFUN_STRAPDOWN', duration='10.0', rate='10.0',
                                nsamp='101', ldt='nsamp'),
    'igea_sim_check_opts': dict(opts=SIM_OPTS, _nan_ok=['opts'], _inf_ok=['opts'], _req=['opts']),
    'igea_sim_model_create': dict(_req=['model']),
    'igea_sim_model_create_trajectory': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                                             ldt='nsamp', nterms='3', terms='[0, 3, 15]',
                                             axes='NULL', nepochs='5',
                                             epochs='c:1.0 + 2.0 * (double)i', _req=['model']),
    'igea_sim_model_set_sigma': dict(growth='0.5'),
    'igea_sim_model_set_noise': dict(opts=SIM_OPTS),
    'igea_sim_model_set_spec': dict(_opt=['spec_sigma']),
    'igea_sim_model_set_truth': dict(x_value='u', x_fixed='[1, 0, 1]', _null_any=['x_value'],
                                     _opt=['x_fixed']),
    'igea_sim_model_set_nonlinear': dict(model='mtraj', on='1', _int=dict(on='enum')),
    'igea_sim_model_get_s': dict(lds='6'),
    'igea_sim_flight': dict(seed='1', flight='0'),
    'igea_sim_interval': dict(k='3.0', n='10.0'),
    'igea_sim_interval_cp': dict(k='3.0', n='10.0', level='0.99'),
    'igea_sim_nonlinear': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                               ldt='nsamp', err='set:b_[0] = 1e-3; b_[15] = 1e-6;'
                               ' for (long i = 1; i < AUDIT_NB; i++) if (i != 15) b_[i] = 0;',
                               axes='NULL', nepochs='5', epochs='c:2.0 * (double)i'),
    'igea_sim_raw': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ, ldt='nsamp',
                         nerr='IGEA_ENVFUN_TERM_END',
                         err='set:for (long i = 0; i < AUDIT_NB; i++) { b_[i] = 0; } b_[0] = 1e-3;'
                             ' b_[15] = 1e-6;',
                         axes='NULL', site=NAV_SITE, frame='IGEA_NAV_ECEF', nepochs='5',
                         epochs='c:2.0 * (double)i', noise='u', ldtel='nsamp', ldtrk='nepochs',
                         _int=dict(frame='enum', nerr='enum'), _opt=['err', 'noise']),
    'igea_sim_raw_track': dict(system='IGEA_ENVFUN_STRAPDOWN', nsamp='101', traj=TRAJ,
                               ldt='nsamp', nerr='IGEA_ENVFUN_TERM_END',
                               err='set:for (long i = 0; i < AUDIT_NB; i++) { b_[i] = 0; }'
                                   ' b_[0] = 1e-3; b_[15] = 1e-6;',
                               axes='NULL', site=NAV_SITE, frame='IGEA_NAV_ECEF', nepochs='5',
                               epochs='c:2.0 * (double)i', trk_err='u', acc_cols='21', acc='u',
                               ldtel='nsamp', ldtrk='nepochs',
                               _int=dict(frame='enum', nerr='enum', acc_cols='enum'),
                               _opt=['err', 'trk_err'], _req=['acc']),
    'igea_sim_track_errors': dict(nepochs='5', sigma_v='pos', sigma_r='10.0', rho='0.5',
                                  cross='0.2', seed='1', flight='0', _opt=['err']),
    'igea_sim_montecarlo': dict(eq_opts=EQ_OPTS, seed='1', first_flight='0', nflights='4',
                                nthreads='1', ldt='nflights', _zero_ok=['nthreads'],
                                _int=dict(nthreads='nonneg'), _nan_out=['counts', 'table']),
    'igea_sim_montecarlo_ex': dict(eq_opts=EQ_OPTS, seed='1', first_flight='0', nflights='4',
                                   nthreads='1', ldt='nflights', ncols='IGEA_SIM_MC_TABLE_COLS_Z',
                                   _zero_ok=['nthreads'],
                                   _int=dict(nthreads='nonneg', ncols='enum'),
                                   _opt=['eq_opts', 'rates', 'comp_tested', 'comp_reject',
                                         'table'],
                                   _nan_out=['counts', 'table']),
    # 7 flights (a partial last group), flight 2 not testable, flight 4 beyond z_0.995
    'igea_sim_pool_ex': dict(nflights='7', ldt='nflights', size='3', eq_opts=EQ_OPTS,
                             _int=dict(size='size'),
                             table='set:for (int i = 0; i < 7; i++) { b_[i] = i == 2 ? 0.0 : 1.0 + i;'
                                   ' b_[7 + i] = i == 2 ? 0.0 : 3.0; b_[14 + i] = i == 4;'
                                   ' b_[21 + i] = NAN; b_[28 + i] = i == 2 ? 0.0 : (i == 4 ? 3.1 : 1.2); }'),
    # 7 flights (a partial last group), flight 2 not testable, flight 4 a rejection
    'igea_sim_pool': dict(nflights='7', ldt='nflights', size='3', _int=dict(size='size'),
                          table='set:for (int i = 0; i < 7; i++) { b_[i] = i == 2 ? 0.0 : 1.0 + i;'
                                ' b_[7 + i] = i == 2 ? 0.0 : 3.0; b_[14 + i] = i == 4;'
                                ' b_[21 + i] = NAN; }'),
    # ---- redund
    'igea_redund_exponential': dict(**{'lambda': '1e-4'}, t='100.0'),
    'igea_redund_reliability_series': dict(n='4', R='c:0.9'),
    'igea_redund_reliability_parallel': dict(n='4', R='c:0.9'),
    'igea_redund_reliability_kofn': dict(n='4', k='2', R='c:0.9'),
    'igea_redund_diagram': dict(ncomp='4', R='[0.9, 0.8, 0.7, 0.6]', nblock='2',
                                type='[IGEA_REDUND_RBD_SERIES, IGEA_REDUND_RBD_KOFN]', k='[0, 2]',
                                first='[0, 2, 5]', member='[0, 1, 2, 3, 4]',
                                _null_any=['k']),
    'igea_redund_seed002': dict(Re1='0.9', Re2='0.95'),
    'igea_redund_geometry': dict(n='6', axes='u', lda='n', R='c:0.9', fdi='1'),
    'igea_stats_erfinv': dict(y='0.3'),
    'igea_redund_confidence_distance': dict(n='4', x='u', ldd='n'),
    'igea_redund_thresholds': dict(n='4', alpha='c:0.9', lda='n', ldd='n'),
    'igea_redund_relation': dict(n='4', D='c:0.5', ldd='n', alpha='c:0.9', lda='n', ldr='n'),
    'igea_redund_relation_delta': dict(n='4', x='u', delta='c:0.5', ldd='n', ldr='n',
                                       _inf_ok=['delta+']),
    'igea_redund_fusion_set': dict(n='4', D='c:0.3 * audit_u01(i)', ldd='n', alpha='c:0.9',
                                   lda='n', iterative='1'),
    'igea_redund_fuse': dict(n='4', x='u', keep='c:1', weighted='1'),
    'igea_redund_false_alarm': dict(sigma_i='1.0', noise_i='0.5', noise_j='0.5',
                                    alpha='0.9'),
    'igea_redund_transform': dict(ngroup='2', C='u', v='u'),
    'igea_redund_parity': dict(m='5', q='3', ldh='m', ldv='m - q'),
    'igea_redund_fdi': dict(m='5', q='3', ldh='m', pfa='0.01'),
    'igea_redund_skew_check': dict(ny='2', ay='u', sy='pos', nz='2', az='u', sz='pos',
                                   ad='0.1', sd='1.0', cy='0.7071', cz='0.7071',
                                   kappa='3.0'),
    'igea_redund_window_count': dict(nsamp='100', fs='10.0', window='2.0'),
    'igea_redund_window_length': dict(fs='10.0', window='2.5'),
    'igea_redund_monitor': dict(nsamp='100', nsens='4', ldy='nsamp', fs='10.0',
                                     window='2.0', alpha='c:0.9', lda='nsens',
                                     iterative='1', weighted='1', nwin='5'),
    'igea_redund_monitor_intervals': dict(nsens='3', nwin='6', fs='10.0', window='0.25',
                                          excluded='[1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 0, 1]',
                                          maxiv='9', _int=dict(maxiv='nonneg'),
                                          _intarr=dict(excluded='flag')),
    'igea_redund_simulate': dict(nsamp='100', nsens='4', fs='10.0', level='u', noise='pos',
                                 fault_sensor='1', t0='2.0', t1='5.0', fault_bias='1.0',
                                 seed='1', ldy='nsamp', _inf_ok=['t0', 't1']),
    # ---- stability
    'igea_stability_block': dict(n='200', fs='10.0', block='2.0'),
    'igea_stability_allan': dict(n='200', fs='10.0', ntau='3', tau='[0.1, 0.2, 0.4]',
                                 kind='IGEA_STABILITY_ALLAN_OVERLAPPING', noise='IGEA_STABILITY_NOISE_AUTO',
                                 conf='0.683', _opt=['lo', 'hi']),
    'igea_stability_taus_used': dict(fs='10.0', ntau='3', tau='[0.25, 0.35, 1.0]'),
    'igea_stability_octave_taus': dict(n='200', fs='10.0', kind='IGEA_STABILITY_ALLAN_OVERLAPPING',
                                       ntau_max='8'),
    'igea_stability_noise_id': dict(ntau='6', tau='c:0.1 * pow(2.0, (double)i)',
                                    adev='c:1e-3 * (1.0 + 0.1 * (double)i)', _nan_out=['out']),
    'igea_stability_dev': dict(n='200', x='u', fs='10.0', data_type='IGEA_STABILITY_DATA_FREQ', ntau='3',
                               tau='[0.1, 0.2, 0.4]', kind='IGEA_STABILITY_ALLAN_OADEV',
                               noise='IGEA_STABILITY_NOISE_AUTO', conf='0.683',
                               _opt=['lo', 'hi', 'edf', 'alpha', 'count', 'tau_used'],
                               _int=dict(data_type='enum'), _req=['tau'],
                               _nan_ok=['x']),  # a NaN is a gap for OADEV (Inf is refused)
    'igea_stability_taus': dict(n='200', fs='10.0', data_type='IGEA_STABILITY_DATA_FREQ',
                                kind='IGEA_STABILITY_ALLAN_OADEV', spacing='IGEA_STABILITY_TAUS_OCTAVE',
                                ntau_max='8', _int=dict(data_type='enum', spacing='enum')),
    'igea_stability_stream_create': dict(fs='10.0', data_type='IGEA_STABILITY_DATA_FREQ',
                                         kind='IGEA_STABILITY_ALLAN_OVERLAPPING',
                                         noise='IGEA_STABILITY_NOISE_AUTO', conf='0.683', ntau='3',
                                         tau='[0.1, 0.2, 0.4]', spacing='IGEA_STABILITY_TAUS_OCTAVE',
                                         block='10.0', _int=dict(data_type='enum', spacing='enum'),
                                         _zero_ok=['ntau'], _req=['tau', 'out']),
    'igea_stability_stream_feed': dict(h='st', n='20', v='u', _zero_ok=['n'], _req=['h', 'v']),
    'igea_stability_stream_samples': dict(h='st'),
    # a fresh stream (nothing fed); descriptor 0 is never read (its octave
    # taus grow with the record: the ring keeps up to 8 MB first)
    'igea_stability_stream_source': dict(h='st0', fd='0', offset='0.0', stride='8',
                                         _int=dict(fd='nonneg', stride='size'),
                                         _extra=[('stride', '4', 'fail'), ('stride', '131080', 'fail'),
                                                 ('offset', '0.5', 'fail'), ('offset', '-8.0', 'fail')]),
    'igea_stability_stream_result': dict(h='st', ntau_max='16',
                                         _opt=['lo', 'hi', 'edf', 'alpha', 'count', 'block']),
    'igea_stability_fit': dict(ntau='8', tau='c:0.1 * pow(2.0, (double)i)',
                               adev='c:1e-3 / sqrt(0.1 * pow(2.0, (double)i)) * (1.0 + 0.05 * (double)(i % 3))',
                               edf='c:200.0 / pow(2.0, (double)i) + 1.0', _opt=['se', 'supported', 'chi2']),
    'igea_stability_fit_boot': dict(n='4096', fs='10.0', kind='IGEA_STABILITY_ALLAN_ADEV', ntau='8',
                                    tau='c:0.1 * pow(2.0, (double)i)',
                                    adev='c:1e-3 / sqrt(0.1 * pow(2.0, (double)i)) * (1.0 + 0.05 * (double)(i % 3))',
                                    edf='c:200.0 / pow(2.0, (double)i) + 1.0', nboot='4', seed='1',
                                    conf='0.9', _opt=['se', 'lo', 'hi', 'supported', 'chi2'],
                                    _int=dict(nboot='size')),
    # ---- rls (handles: m = 3 coefficients, k = 2 rows)
    # ---- noise (igea/noise.h)
    'igea_whiten_create': dict(N='3', p='1', phi='[0.5, 0.3, -0.2]', ngroups='2',
                               _req=['phi', 'w'], _int=dict(p='nonneg', ngroups='size')),
    'igea_whiten_free': dict(w='w'),
    'igea_whiten_reset': dict(w='w'),
    'igea_whiten_get_state': dict(w='w'),
    'igea_whiten_accumulate': dict(w='w', m='6', S='u', lds='m', dw='u', track_sigma='pos',
                                   sigma_inc='1', cov='NULL', group='[0, 1]',
                                   mask='[0, 0, 1, 0, 0, 0]', A='0', lda='3', b='0', wtw='0',
                                   _zero_ok=['m'], _req=['track_sigma'],
                                   _intarr=dict(group='code', mask='flag'),
                                   _neg_bad={'wtw': [0, 1, 2, 3]}),
    'igea_whiten_accumulate_xcov': dict(w='wx', m='6', S='u', lds='m', dw='u',
                                        cov='set:{ double x9[18]; audit_whole_k(2, 2, 1.0, b_, x9); }',
                                        xcov='set:{ double k6[12]; audit_whole_k(2, 2, 1.0, k6, b_); }',
                                        mask='[0, 0, 1, 0, 0, 0]', A='0', lda='3', b='0',
                                        wtw='0', _zero_ok=['m'], _intarr=dict(mask='flag'),
                                        _neg_bad={'wtw': [0, 1]}),
    'igea_noise_ar_fit': dict(M='8', p='1', resid='u', group='NULL', mask='NULL',
                              _int=dict(M='size', p='size'),
                              _intarr=dict(group='code', mask='flag')),
    'igea_noise_vce': dict(N='3', G='2', A='set:audit_spd(b_, 3, 3, 10.0); '
                           'audit_spd(b_ + 9, 3, 3, 5.0);', lda='N', b='c:0.1 * au(i)',
                           wtw='[5.0, 6.0, 4.0, 6.0]', tol='1e-8', max_iter='200',
                           _int=dict(G='size', max_iter='size')),
    'igea_noise_vce_cov': dict(N='3', G='2', A='set:audit_spd(b_, 3, 3, 10.0); '
                               'audit_spd(b_ + 9, 3, 3, 5.0);', lda='N',
                               wtw='[5.0, 6.0, 4.0, 6.0]', scale='[1.0, 2.0]',
                               _int=dict(G='size')),
    'igea_noise_eqerr': dict(m='12', N='3', S='u', lds='m', dw='c:au(i + 5000)',
                             track_sigma='c:0.05',
                             sigma_inc='1', cov='NULL', group='[0, 0, 1, 1]', ngroups='2',
                             phi='[0.3, 0.2, 0.1]',
                             opts='set:igea_eqerr_defaults(b_); b_[IGEA_EQERR_OPT_AR] = 1;'
                                  ' b_[IGEA_EQERR_OPT_ROBUST] = 1;',
                             _req=['S', 'dw', 'z', 'track_sigma', 'group'],
                             _int=dict(ngroups='size'), _intarr=dict(group='code')),
    'igea_noise_eqerr_resid': dict(m='12', N='3', S='u', lds='m', dw='c:au(i + 5000)',
                                   track_sigma='c:0.05',
                                   sigma_inc='1', cov='NULL', group='[0, 0, 1, 1]',
                                   ngroups='2', phi='[0.3, 0.2, 0.1]',
                                   opts='set:igea_eqerr_defaults(b_); b_[IGEA_EQERR_OPT_AR] = 1;'
                                        ' b_[IGEA_EQERR_OPT_ROBUST] = 1;',
                                   _req=['S', 'dw', 'z', 'track_sigma', 'group'],
                                   _int=dict(ngroups='size'), _intarr=dict(group='code')),
    'igea_noise_eqerr_xcov': dict(m='12', N='3', S='u', lds='m', dw='c:au(i + 5000)',
                                  cov='set:{ double x9[36]; audit_whole_k(0, 4, 0.0025, b_, x9); }',
                                  xcov='set:{ double k6[24]; audit_whole_k(0, 4, 0.0025, k6, b_); }',
                                  opts='set:igea_eqerr_defaults(b_); b_[IGEA_EQERR_OPT_ROBUST] = 1;',
                                  _req=['S', 'dw', 'z', 'cov', 'xcov']),
    'igea_rls_create': dict(m='3', k='2', x0='u', gamma0='set:audit_spd(b_, 3, 3, 1.0);',
                            ldg='m'),
    'igea_rls_set_variant': dict(variant='IGEA_RLS_POLYNOMIAL', p='3'),
    'igea_rls_set_anomaly': dict(policy='IGEA_RLS_ANOMALY_SKIP', kappa='4.0', jump_max='pos',
                                 _valid=['kappa=+Inf', 'jump_max[0]=+Inf']),
    'igea_rls_set_covariance': dict(h='h0', track='1'),
    'igea_rls_set_forget': dict(forget='0.99'),
    'igea_rls_update': dict(c='u', ldc='2', y='u', track_sigma='pos'),
    'igea_rls_run': dict(n='4', layout='IGEA_COLMAJOR', S='u', lds='8', dw='u',
                         track_sigma='pos', sigma_inc='1', ldx='3', _zero_ok=['n'],
                         _opt=['track_sigma'], _progress=['n_done']),
    'igea_rls_get_gamma': dict(ldg='3'),
    'igea_rls_get_covariance': dict(ldc='3'),
    'igea_rls_compensate': dict(c='u', ldc='2', y='u'),
    # ---- io (handles: 'io' a reader open on audit_io_path(), 3 x 2 with
    # names; 'io0' created only, 'io2' opened for two passes, 'iol' loaded)
    'igea_io_reader_create': dict(_req=['out']),
    'igea_io_reader_open': dict(r='io0', path='set:audit_io_file((char *)b_);', flags='0',
                                tmpdir='NULL', _int=dict(flags='enum'), _opt=['tmpdir'], _req=['r', 'path'],
                                _intarr=dict(path='free', tmpdir='free')),
    'igea_io_reader_open_fd': dict(r='io0', fd='audit_io_fd()', name='set:memcpy(b_, "m.txt", 6);',
                                   flags='0', tmpdir='NULL', _opt=['name', 'tmpdir'],
                                   _int=dict(fd='nonneg', flags='enum'),
                                   _intarr=dict(name='free', tmpdir='free')),
    'igea_io_reader_cols': dict(_opt=['r']),
    'igea_io_reader_names': dict(_opt=['r']),
    'igea_io_reader_message': dict(_opt=['r']),
    'igea_io_reader_next': dict(maxrows='2', _int=dict(maxrows='size'), _progress=['buf'],
                                _req=['r', 'buf', 'nread']),
    'igea_io_reader_view': dict(maxrows='2', _int=dict(maxrows='size'), _req=['r', 'nread']),
    'igea_io_reader_view_rows': dict(_opt=['r']),
    'igea_io_reader_view_check': dict(_req=['r']),
    'igea_io_reader_rewind': dict(r='io2', _req=['r']),
    'igea_io_reader_load': dict(_req=['r']),
    'igea_io_reader_info': dict(_req=['r', 'info']),
    'igea_io_reader_copy': dict(r='iol', layout='IGEA_ROWMAJOR', _req=['r', 'v']),
    'igea_io_parse_number': dict(s='set:memcpy(b_, "1.5D+01", 8);', _intarr=dict(s='free')),
}

# Further baselines of some functions, for the branches the first one does
# not reach (fewer rows than terms, other rules, routes, models, layouts).
# Each inherits the function's BASE entry; its checks are named
# "FUNCTION@VARIANT".
WIDE = dict(m='2', N='5')
VARIANTS = {
    'igea_normal_qr_accumulate': dict(rowmajor=dict(layout='IGEA_ROWMAJOR', lds='N')),
    'igea_eqerr_run': dict(svd=dict(opts='set:igea_eqerr_defaults(b_);'
                                         ' b_[IGEA_EQERR_OPT_ROUTE] = IGEA_EQERR_ROUTE_SVD;'),
                           huge=dict(S='c:1e200 * au(i)', _expect='any'),
                           wide=dict(m='3', N='5', _expect='any'),
                           tiny_sigma=dict(track_sigma='c:1e-310', _expect='any'),
                           threads=dict(opts='set:igea_eqerr_defaults(b_);'
                                             ' b_[IGEA_EQERR_OPT_THREADS] = 2;')),
    'igea_eqerr_run_layout': dict(rows=dict(layout='IGEA_ROWMAJOR', lds='N'),
                                  rows_svd=dict(layout='IGEA_ROWMAJOR', lds='N',
                                                opts='set:igea_eqerr_defaults(b_);'
                                                     ' b_[IGEA_EQERR_OPT_ROUTE] = '
                                                     'IGEA_EQERR_ROUTE_SVD;'),
                                  rows_threads=dict(layout='IGEA_ROWMAJOR', lds='N',
                                                    opts='set:igea_eqerr_defaults(b_);'
                                                         ' b_[IGEA_EQERR_OPT_THREADS] = 3;')),
    'igea_regress_ridge': dict(wide=WIDE, hkb=dict(rule='IGEA_REGRESS_RIDGE_HKB', _ignored=['k']),
                               lw=dict(rule='IGEA_REGRESS_RIDGE_LW', _ignored=['k']),
                               gcv=dict(rule='IGEA_REGRESS_RIDGE_GCV', _ignored=['k']),
                               loo=dict(rule='IGEA_REGRESS_RIDGE_LOO', _ignored=['k']),
                               wide_gcv=dict(WIDE, rule='IGEA_REGRESS_RIDGE_GCV', _ignored=['k']),
                               tiny=dict(A='c:1e-300 * au(i)', rule='IGEA_REGRESS_RIDGE_HKB',
                                         _expect='any'),
                               col_huge=dict(A='c:(i >= 12 ? 1e300 : 1.0) * au(i)',
                                             rule='IGEA_REGRESS_RIDGE_HKB', _expect='any')),
    'igea_regress_ridge_trace': dict(wide=WIDE),
    'igea_regress_pce': dict(wide=WIDE, ncomp2=dict(ncomp='2', _ignored=['eig_min'])),
    'igea_regress_pce_ex': dict(wide=WIDE, ncomp2=dict(ncomp='2', _ignored=['eig_min']),
                                scaled=dict(A='c:(i >= 12 ? 1e-12 : 1.0) * au(i)')),
    'igea_regress_ridge_ex': dict(wide=WIDE, scaled=dict(A='c:(i >= 12 ? 1e-12 : 1.0) * au(i)'),
                                  hkb=dict(rule='IGEA_REGRESS_RIDGE_HKB', _ignored=['k'])),
    'igea_regress_bayes': dict(wide=dict(WIDE, prior_cov='set:audit_spd(b_, 5, 5, 1.0);')),
    'igea_regress_collinearity': dict(wide=WIDE),
    'igea_regress_ebr': dict(mm=dict(rule='IGEA_REGRESS_EBR_MM'), ml2=dict(rule='IGEA_REGRESS_EBR_ML2'),
                             tiny=dict(A='c:1e-300 * au(i)', _expect='any'),
                             wide=dict(m='4', N='6', _expect='any')),
    'igea_regress_ls': dict(wide=WIDE, one_row=dict(m='1', N='4'),
                            tiny=dict(A='c:1e-300 * au(i)', _expect='any')),
    'igea_regress_ls_ex': dict(wide=WIDE, one_row=dict(m='1', N='4'),
                               norefine=dict(flags='IGEA_REGRESS_NO_REFINE'),
                               tiny=dict(A='c:1e-300 * au(i)', _expect='any')),
    'igea_accel_fit': dict(ls=dict(method='IGEA_ACCEL_LS',
                                   _ignored=['prior_scale', 'rule', 'lam_floor']),
                           few=dict(method='IGEA_ACCEL_LS', n='4', theta_deg='c:90.0 * (double)i',
                                    _nan_out=['sd', 'comb_sd'],
                                    _ignored=['prior_scale', 'rule', 'lam_floor']),
                           few_ebr=dict(n='4', theta_deg='c:90.0 * (double)i', _expect='any'),
                           single=dict(model='IGEA_ACCEL_SINGLE', yb='NULL',
                                       ya='c:asind(30.0 * (double)i) + 1e-4 * au(i)')),
    'igea_accel_analyze': dict(single=dict(model='IGEA_ACCEL_SINGLE', ldn='5'),
                               few=dict(n='4', theta_deg='c:90.0 * (double)i')),
    'igea_accel_design': dict(single=dict(model='IGEA_ACCEL_SINGLE')),
    'igea_accel_fit_prior': dict(single=dict(model='IGEA_ACCEL_SINGLE', yb='NULL', ldp='5',
                                             ldc='5', _ignored=['yb'], _req=[],
                                             prior_cov='set:for (int i = 0; i < 25; i++) '
                                                       'b_[i] = i % 6 == 0 ? 1e-8 : 0.0;')),
    'igea_accel_ieee_fit': dict(harmonic=dict(method='IGEA_ACCEL_HARMONIC'),
                                one_plane=dict(plane='0'),
                                few=dict(n='6', _nan_out=['sd', 'cov'])),
    'igea_accel_criterion': dict(ieee=dict(model='IGEA_ACCEL_IEEE', method='IGEA_ACCEL_LS',
                                           n='16', theta_deg=IEEE_THETA, plane='c:i < 8 ? 0 : 1',
                                           _req=['plane'], _ignored=['head_ratio'],
                                           _intarr=dict(plane='code')),
                                 single=dict(model='IGEA_ACCEL_SINGLE', method='IGEA_ACCEL_LS',
                                             _ignored=['head_ratio', 'plane'])),
    'igea_accel_apply': dict(single=dict(model='IGEA_ACCEL_SINGLE', raw_b='NULL',
                                         cross='c:acosd(30.0 * (double)i)',
                                         _ignored=['scale_b', 'v'])),
    'igea_envfun_compute': dict(platform=dict(
        system='IGEA_ENVFUN_PLATFORM', terms='[0, 15, 27, 33]', nterms='4',
        traj='set:igea_sim_trajectory(IGEA_ENVFUN_PLATFORM, 10.0, 10.0, 101, b_, 101);',
        axes='[0, 1, 2, 1, 2, 0]', output='IGEA_ENVFUN_POSITION_G')),
    'igea_sim_trajectory': dict(platform=dict(system='IGEA_ENVFUN_PLATFORM')),
    'igea_sim_montecarlo': dict(threads=dict(nthreads='2'), traj=dict(model='mtraj'),
                                nonlinear=dict(model='mnl')),
    'igea_sim_montecarlo_ex': dict(threads=dict(nthreads='2'), traj=dict(model='mtraj')),
    'igea_sim_flight': dict(traj=dict(model='mtraj'), nonlinear=dict(model='mnl')),
    'igea_redund_geometry': dict(span=dict(fdi='0', _nan_out=['out'])),
    'igea_redund_fusion_set': dict(oneshot=dict(iterative='0')),
    'igea_rls_update': dict(poly=dict(h='hpoly'),
                            isolate=dict(h='hiso', _valid=['y[0]=NaN', 'y[0]=+Inf', 'y[0]=-Inf'])),
    'igea_rls_run': dict(poly=dict(h='hpoly')),
    'igea_rls_get_covariance': dict(poly=dict(h='hpoly')),
    # large or tiny finite data: a verdict, or a clean refusal, never NaN
    'igea_stats_accuracy_test': dict(huge=dict(equiv_err='c:i == 0 ? 1e300 : au(i)')),
    'igea_stats_pool': dict(huge=dict(chi2='[1e308, 1e308, 1.5]')),
    'igea_whiten_accumulate': dict(cov=dict(track_sigma='NULL', _req=['cov'],
                                            cov='set:for (int e = 0; e < 2; e++) { double c6[6] = '
                                                '{1.0, 0.2, 1.0, 0.1, 0.3, 1.0}; '
                                                'for (int k = 0; k < 6; k++) b_[6 * e + k] = c6[k]; }')),
    'igea_noise_eqerr': dict(cov=dict(track_sigma='NULL', _req=['S', 'dw', 'z', 'cov', 'group'],
                                      cov='set:for (int e = 0; e < 4; e++) { double c6[6] = '
                                          '{0.01, 0.002, 0.01, 0.001, 0.003, 0.01}; '
                                          'for (int k = 0; k < 6; k++) b_[6 * e + k] = c6[k]; }'),
                             estimate=dict(opts='set:igea_eqerr_defaults(b_);'
                                                ' b_[IGEA_EQERR_OPT_AR] = 1;'
                                                ' b_[IGEA_EQERR_OPT_AR_ESTIMATE] = 1;'
                                                ' b_[IGEA_EQERR_OPT_GROUP_BIAS] = 0;',
                                           m='24', group='[0, 0, 0, 0, 1, 1, 1, 1]')),
    'igea_normal_accumulate': dict(rowmajor=dict(layout='IGEA_ROWMAJOR', lds='N'),
                                   huge=dict(S='c:1e200 * au(i)', _expect='any')),
    'igea_stability_allan': dict(modified=dict(kind='IGEA_STABILITY_ALLAN_MODIFIED', noise='IGEA_STABILITY_NOISE_WFM'),
                                 nonoverlapping=dict(kind='IGEA_STABILITY_ALLAN_NONOVERLAPPING')),
    'igea_stability_dev': dict(
        phase_mtotdev=dict(data_type='IGEA_STABILITY_DATA_PHASE', kind='IGEA_STABILITY_ALLAN_MTOTDEV',
                           noise='IGEA_STABILITY_NOISE_AUTO'),
        theo1=dict(kind='IGEA_STABILITY_ALLAN_THEO1', tau='[0.15, 0.3, 1.5]'),
        theobr=dict(kind='IGEA_STABILITY_ALLAN_THEOBR', tau='[0.15, 0.3, 1.5]'),
        theoh=dict(kind='IGEA_STABILITY_ALLAN_THEOH', tau='[0.1, 0.2, 4.5]'),
        mtie=dict(kind='IGEA_STABILITY_ALLAN_MTIE', lo='NULL', hi='NULL', edf='NULL'),
        htotdev=dict(kind='IGEA_STABILITY_ALLAN_HTOTDEV')),
}
