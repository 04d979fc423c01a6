/* igea accel - dividing-head accelerometer calibration (seed 003). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void help(void)
{
    printf(
        "usage: igea accel [options] FILE\n"
        "\n"
        "Calibrates accelerometers in the gravity field from a multi-position tumble\n"
        "on a dividing head turning about a horizontal axis (METHODS 4.1-4.3).\n"
        "\n"
        "FILE holds one row per reading: head angle (deg), A output, B output\n"
        "(text or .npy; '#' comments). Rows of the clockwise and counter-clockwise\n"
        "runs at the same angle are averaged, and the 360 deg reading is averaged\n"
        "with the 0 deg one. Outputs are in g, or raw (e.g. volts) with\n"
        "--scale-a/--scale-b, the nominal scale factors in output units per g.\n"
        "\n"
        "Models:\n"
        "  dual    orthogonal pair, g^2 observation (y_A^2 + y_B^2 - 1)/2: the head\n"
        "          angle errors cancel, but KA0, KA2, KBix and KB0, KB2, KAix are\n"
        "          coupled (rank 7 of 9); their individual values are flagged PRIOR:\n"
        "          they come from the minimum-norm convention (ls) or the prior (ebr),\n"
        "          not from the data. The estimable combinations are reported with sds.\n"
        "  single  accelerometer A alone, y_A - sin(theta) on [1, s, c, s^2, sc]: all\n"
        "          five coefficients identifiable, head errors enter as noise.\n"
        "\n"
        "Options:\n"
        "  --model dual|single   (default dual; single reads the first two columns)\n"
        "  --method ls|ebr       least squares (default) or empirical-Bayes ridge\n"
        "  --prior FILE          EBR prior scales tau_j, one per coefficient (9 dual,\n"
        "                        5 single), e.g. historical spreads\n"
        "  --rule sc|mm|ml2      EBR rule for lambda (default sc, METHODS 4.3 eq. 17)\n"
        "  --lam-floor X         EBR lower bound on lambda (default 0)\n"
        "  --scale-a K, --scale-b K  nominal scale factors (default 1: outputs in g)\n"
        "  --tol DEG             readings this close form one position (default 1e-6)\n"
        "  --axis pa|oa          rotation axis, names the cross-coupling Kio (pa, the\n"
        "                        door position; default) or Kip (oa)\n"
        "  --refine              dual: Gauss-Newton on the exact models (1)-(2) after\n"
        "                        the linear fit (for mg-level biases); the null-space\n"
        "                        part of the fit is kept\n"
        "  --json                machine-readable output\n"
        "  --out FILE            write the report to FILE (atomically)\n"
        "\n"
        "Example (the seed's 20-position experiment, 0..360 deg both ways):\n"
        "  igea accel examples/accel_dual.txt\n"
        "  igea accel --method ebr --prior examples/accel_prior.txt examples/accel_dual.txt\n"
        "  igea accel --model single --json examples/accel_dual.txt\n"
        "\n"
        "Exit status: 0 ok, 64 usage, 65 bad input, 66 missing input, 70 numerical\n"
        "failure, 74 output error.\n");
}

static const char *names_dual[2][9] = {
    {"KA0", "KB0", "kA1", "kB1", "eta", "KA2", "KB2", "KAio", "KBio"},
    {"KA0", "KB0", "kA1", "kB1", "eta", "KA2", "KB2", "KAip", "KBip"}};
static const char *names_single[2][5] = {{"K0", "k1", "delta0", "K2", "Kio"},
                                         {"K0", "k1", "delta0", "K2", "Kip"}};
static const char *comb_dual[2][7] = {
    {"kA1", "kB1", "eta", "KA0+KA2", "KA2+KBio", "KB0+KB2", "KB2-KAio"},
    {"kA1", "kB1", "eta", "KA0+KA2", "KA2+KBip", "KB0+KB2", "KB2-KAip"}};
static const char *units_dual[9] = {"g", "g", "", "", "rad", "g/g^2", "g/g^2", "g/g^2",
                                    "g/g^2"};
static const char *units_single[5] = {"g", "", "rad", "g/g^2", "g/g^2"};

static void json_names(FILE *f, const char *const *names, int n)
{
    fputc('[', f);
    for (int i = 0; i < n; i++) {
        if (i)
            fputs(", ", f);
        cli_json_str(f, names[i]);
    }
    fputc(']', f);
}

int cmd_accel(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    const char *path = NULL, *prior_path = NULL, *out_path = NULL;
    int model = IGEA_ACCEL_DUAL, method = IGEA_ACCEL_LS, rule = IGEA_REGRESS_EBR_SC;
    int json = 0, refine = 0, axis = 0;
    double lam_floor = 0.0, scale_a = 1.0, scale_b = 1.0, tol = 1e-6;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            help();
            return CLI_OK;
        } else if (!strcmp(a, "--json")) {
            json = 1;
        } else if (!strcmp(a, "--refine")) {
            refine = 1;
        } else if (!strcmp(a, "--model") || !strcmp(a, "--method") || !strcmp(a, "--rule") ||
                   !strcmp(a, "--axis")) {
            if (!(v = cli_optarg(argc, argv, &i)))
                return CLI_USAGE;
            int ok = 1;
            if (!strcmp(a, "--model")) {
                if (!strcmp(v, "dual"))
                    model = IGEA_ACCEL_DUAL;
                else if (!strcmp(v, "single"))
                    model = IGEA_ACCEL_SINGLE;
                else
                    ok = 0;
            } else if (!strcmp(a, "--method")) {
                if (!strcmp(v, "ls"))
                    method = IGEA_ACCEL_LS;
                else if (!strcmp(v, "ebr"))
                    method = IGEA_ACCEL_EBR;
                else
                    ok = 0;
            } else if (!strcmp(a, "--rule")) {
                if (!strcmp(v, "sc"))
                    rule = IGEA_REGRESS_EBR_SC;
                else if (!strcmp(v, "mm"))
                    rule = IGEA_REGRESS_EBR_MM;
                else if (!strcmp(v, "ml2"))
                    rule = IGEA_REGRESS_EBR_ML2;
                else
                    ok = 0;
            } else {
                if (!strcmp(v, "pa"))
                    axis = 0;
                else if (!strcmp(v, "oa"))
                    axis = 1;
                else
                    ok = 0;
            }
            if (!ok) {
                cli_error("accel: option %s: unknown value '%s' (see igea accel --help)", a, v);
                return CLI_USAGE;
            }
        } else if (!strcmp(a, "--prior") || !strcmp(a, "--out")) {
            if (!(v = cli_optarg(argc, argv, &i)))
                return CLI_USAGE;
            if (!strcmp(a, "--prior"))
                prior_path = v;
            else
                out_path = v;
        } else if (!strcmp(a, "--lam-floor") || !strcmp(a, "--scale-a") ||
                   !strcmp(a, "--scale-b") || !strcmp(a, "--tol")) {
            if (!(v = cli_optarg(argc, argv, &i)))
                return CLI_USAGE;
            double *dst = !strcmp(a, "--lam-floor") ? &lam_floor
                          : !strcmp(a, "--scale-a") ? &scale_a
                          : !strcmp(a, "--scale-b") ? &scale_b
                                                    : &tol;
            if (cli_parse_double(a, v, dst))
                return CLI_USAGE;
        } else if (a[0] == '-' && a[1] != '\0') {
            cli_error("accel: unknown option '%s' (see igea accel --help)", a);
            return CLI_USAGE;
        } else if (!path) {
            path = a;
        } else {
            cli_error("accel: one input file expected, got '%s' too", a);
            return CLI_USAGE;
        }
    }
    if (!path) {
        cli_error("accel: no input file (see igea accel --help)");
        return CLI_USAGE;
    }
    if (scale_a == 0.0 || scale_b == 0.0) {
        cli_error("accel: a scale factor must not be 0");
        return CLI_USAGE;
    }
    if (!(tol >= 0.0 && tol < 45.0)) {
        cli_error("accel: --tol must be in [0, 45) degrees");
        return CLI_USAGE;
    }
    if (lam_floor < 0.0) {
        cli_error("accel: --lam-floor must be >= 0");
        return CLI_USAGE;
    }
    if (refine && model != IGEA_ACCEL_DUAL) {
        cli_error("accel: --refine needs the dual model");
        return CLI_USAGE;
    }
    if (prior_path && method != IGEA_ACCEL_EBR) {
        cli_error("accel: --prior needs --method ebr");
        return CLI_USAGE;
    }
    const int np = model == IGEA_ACCEL_DUAL ? IGEA_ACCEL_NP_DUAL : IGEA_ACCEL_NP_SINGLE;
    const int nc = model == IGEA_ACCEL_DUAL ? IGEA_ACCEL_NC_DUAL : IGEA_ACCEL_NC_SINGLE;
    const int need_cols = model == IGEA_ACCEL_DUAL ? 3 : 2;
    const char *const *names = model == IGEA_ACCEL_DUAL ? names_dual[axis] : names_single[axis];
    const char *const *cnames = model == IGEA_ACCEL_DUAL ? comb_dual[axis] : names_single[axis];
    const char *const *units = model == IGEA_ACCEL_DUAL ? units_dual : units_single;

    cli_matrix in = {0}, pr = {0};
    int ec = cli_read_matrix(path, &in);
    if (ec)
        return ec;
    if (in.cols < need_cols) {
        cli_error("%s: %d column(s); expected angle, A output%s per row", path, in.cols,
                  model == IGEA_ACCEL_DUAL ? ", B output" : "");
        cli_matrix_free(&in);
        return CLI_DATAERR;
    }
    if (in.rows > 10000000L) {
        cli_error("%s: too many rows", path);
        cli_matrix_free(&in);
        return CLI_DATAERR;
    }
    double tau[9];
    if (prior_path) {
        ec = cli_read_matrix(prior_path, &pr);
        if (ec) {
            cli_matrix_free(&in);
            return ec;
        }
        if (pr.rows * pr.cols != np) {
            cli_error("%s: %ld value(s); the prior needs %d scales (one per coefficient)",
                      prior_path, pr.rows * (long)pr.cols, np);
            cli_matrix_free(&in);
            cli_matrix_free(&pr);
            return CLI_DATAERR;
        }
        memcpy(tau, pr.v, (size_t)np * sizeof(double));
        cli_matrix_free(&pr);
    }
    int nr = (int)in.rows;
    double *buf = malloc((size_t)nr * 7 * sizeof(double) + 1);
    int *cnt = malloc((size_t)nr * sizeof(int) + 1);
    if (!buf || !cnt) {
        free(buf);
        free(cnt);
        cli_matrix_free(&in);
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    double *ang = buf, *ya = ang + nr, *yb = ya + nr, *th = yb + nr, *ma = th + nr,
           *mb = ma + nr, *phi = mb + nr;
    for (int i = 0; i < nr; i++) {
        ang[i] = in.v[(size_t)i * in.cols];
        ya[i] = in.v[(size_t)i * in.cols + 1];
        yb[i] = model == IGEA_ACCEL_DUAL ? in.v[(size_t)i * in.cols + 2] : 0.0;
    }
    cli_matrix_free(&in);
    int npos = 0;
    double coef[9], sd[9], cmb[7], csd[7], info[IGEA_ACCEL_INFO_LEN];
    double rcoef[9], rsd[9], rinfo[IGEA_ACCEL_INFO_LEN], rcmb[7], C[63];
    int flag[9];
    int st = igea_accel_to_g(nr, ya, scale_a, ya);
    if (!st && model == IGEA_ACCEL_DUAL)
        st = igea_accel_to_g(nr, yb, scale_b, yb);
    if (!st)
        st = igea_accel_merge(nr, ang, ya, model == IGEA_ACCEL_DUAL ? yb : NULL, tol, th, ma,
                              model == IGEA_ACCEL_DUAL ? mb : NULL, cnt, &npos);
    if (!st)
        st = igea_accel_fit(model, method, npos, th, ma, mb, prior_path ? tau : NULL, rule,
                            lam_floor, coef, sd, flag, cmb, csd, info);
    if (st) {
        free(buf);
        free(cnt);
        return cli_status(st, "accel");
    }
    if (refine) {
        st = igea_accel_refine(npos, th, ma, mb, coef, 100, 1e-13, rcoef, rsd, phi, rinfo);
        if (!st)
            st = igea_accel_combinations(IGEA_ACCEL_DUAL, C, 9);
        if (st) {
            free(buf);
            free(cnt);
            return cli_status(st, "accel --refine");
        }
        for (int k = 0; k < nc; k++) {
            rcmb[k] = 0.0;
            for (int j = 0; j < np; j++)
                rcmb[k] += C[j + k * 9] * rcoef[j];
        }
    }
    cli_out o;
    ec = cli_out_open(&o, out_path);
    if (ec) {
        free(buf);
        free(cnt);
        return ec;
    }
    FILE *f = o.f;
    const char *mname = model == IGEA_ACCEL_DUAL ? "dual" : "single";
    const char *meth = method == IGEA_ACCEL_LS ? "ls" : "ebr";
    if (json) {
        fprintf(f, "{\"model\": \"%s\", \"method\": \"%s\", \"positions\": %d, \"readings\": %d,\n",
                mname, meth, npos, nr);
        fputs(" \"theta_deg\": ", f);
        cli_json_array(f, th, npos);
        fputs(",\n \"readings_per_position\": ", f);
        cli_json_iarray(f, cnt, npos);
        fputs(",\n \"names\": ", f);
        json_names(f, names, np);
        fputs(",\n \"coef\": ", f);
        cli_json_array(f, coef, np);
        fputs(",\n \"sd\": ", f);
        cli_json_array(f, sd, np);
        fputs(",\n \"flags\": [", f);
        for (int j = 0; j < np; j++)
            fprintf(f, "%s\"%s\"", j ? ", " : "", flag[j] ? "prior" : "data");
        fputs("],\n \"comb_names\": ", f);
        json_names(f, cnames, nc);
        fputs(",\n \"comb\": ", f);
        cli_json_array(f, cmb, nc);
        fputs(",\n \"comb_sd\": ", f);
        cli_json_array(f, csd, nc);
        fprintf(f, ",\n \"rank\": %d, \"dof\": %d, \"sigma\": ", (int)info[IGEA_ACCEL_INFO_RANK],
                (int)info[IGEA_ACCEL_INFO_DOF]);
        cli_json_num(f, info[IGEA_ACCEL_INFO_SIGMA]);
        fputs(", \"rms\": ", f);
        cli_json_num(f, info[IGEA_ACCEL_INFO_RMS]);
        fputs(", \"lam\": ", f);
        cli_json_num(f, info[IGEA_ACCEL_INFO_LAMBDA]);
        if (refine) {
            fputs(",\n \"refined\": {\"coef\": ", f);
            cli_json_array(f, rcoef, np);
            fputs(", \"sd\": ", f);
            cli_json_array(f, rsd, np);
            fputs(", \"comb\": ", f);
            cli_json_array(f, rcmb, nc);
            fputs(", \"phi_deg\": ", f);
            cli_json_array(f, phi, npos);
            fprintf(f, ", \"iterations\": %d, \"sigma\": ", (int)rinfo[IGEA_ACCEL_INFO_ITER]);
            cli_json_num(f, rinfo[IGEA_ACCEL_INFO_SIGMA]);
            fputc('}', f);
        }
        fputs("}\n", f);
    } else {
        fprintf(f, "igea accel: %s model, %s; %d readings -> %d positions; rank %d, "
                   "dof %d\n", mname, method == IGEA_ACCEL_LS ? "least squares" :
                   "empirical-Bayes ridge", nr, npos, (int)info[IGEA_ACCEL_INFO_RANK],
                (int)info[IGEA_ACCEL_INFO_DOF]);
        fprintf(f, "residual sd %.3e g, rms %.3e g", info[IGEA_ACCEL_INFO_SIGMA],
                info[IGEA_ACCEL_INFO_RMS]);
        if (method == IGEA_ACCEL_EBR)
            fprintf(f, ", lambda %.6g%s", info[IGEA_ACCEL_INFO_LAMBDA],
                    prior_path ? " (prior-scaled)" : " (isotropic prior)");
        fputc('\n', f);
        fprintf(f, "\n%-9s %-6s %15s %12s  %s\n", "coef", "unit", "estimate", "sd",
                "determined by");
        for (int j = 0; j < np; j++)
            fprintf(f, "%-9s %-6s %15.6e %12.3e  %s\n", names[j], units[j], coef[j], sd[j],
                    flag[j] ? (method == IGEA_ACCEL_LS ? "PRIOR (minimum-norm convention)"
                                                       : "PRIOR (not from the data)")
                            : "data");
        int anyprior = 0;
        for (int j = 0; j < np; j++)
            anyprior |= flag[j];
        if (anyprior)
            fprintf(f, "PRIOR: the calibration holds no information on these coefficients "
                       "one by one;\ntheir values and sds follow the %s, not the instrument: "
                       "use the estimable\ncombinations below.\n",
                    method == IGEA_ACCEL_LS ? "minimum-norm convention" : "prior");
        fprintf(f, "\n%-9s %15s %12s\n", "estimable", "estimate", "sd");
        for (int k = 0; k < nc; k++)
            fprintf(f, "%-9s %15.6e %12.3e\n", cnames[k], cmb[k], csd[k]);
        if (refine) {
            fprintf(f, "\nexact-model refinement (%d iterations, residual sd %.3e g per "
                       "output):\n", (int)rinfo[IGEA_ACCEL_INFO_ITER],
                    rinfo[IGEA_ACCEL_INFO_SIGMA]);
            for (int j = 0; j < np; j++)
                fprintf(f, "%-9s %15.6e %12.3e  %s\n", names[j], rcoef[j], rsd[j],
                        flag[j] ? "null part kept from the fit" : "data");
            for (int k = 0; k < nc; k++)
                fprintf(f, "%-9s %15.6e\n", cnames[k], rcmb[k]);
        }
    }
    free(buf);
    free(cnt);
    return cli_out_commit(&o);
}
