/* igea impact - the impact point of the free flight from a burnout state,
 * its sensitivity, the error budget in miss distance and the CEP
 * (include/igea/impact.h, docs/impact.md). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *burnout, *errors, *names, *out, *terms, *spec;
    const char *plot; /* --plot FILE.svg */
    double prob, opts[IGEA_IMPACT_OPT_LEN];
    int model, json, given_spec, given_prob;
    cli_burnout_args bo; /* --burnout-time, --traj and the launch point */
} im_args;

static im_args A;

static const cli_opt options[] = {
    {"--burnout", CLI_OPT_STR, &A.burnout, NULL, "X,Y,Z,VX,VY,VZ|FILE",
     "burnout position (m) and velocity relative to the\nEarth (m/s) in ECEF: six numbers or a file of them\n(or --burnout-time)", NULL},
    {"--model", CLI_OPT_CHOICE, &A.model, "kepler", CLI_CHOICES(IGEA_CHOICE_IMPACT_MODEL),
     "spherical Earth in closed form, or with J2 integrated", NULL},
    {"--mu", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_MU], CLI_DEF_LIB, "MU", "gravitational parameter (m^3/s^2)", NULL},
    {"--radius", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_RADIUS], CLI_DEF_LIB, "R", "radius of the impact sphere (m)", NULL},
    {"--omega", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_OMEGA], CLI_DEF_LIB, "W", "Earth rate (rad/s; 0: no rotation)", NULL},
    {"--j2", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_J2], CLI_DEF_LIB, "J2", "J2 (the j2 model)", NULL},
    {"--re", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_RE], CLI_DEF_LIB, "RE", "J2 reference radius (m)", NULL},
    {"--step", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_STEP], CLI_DEF_LIB, "S", "J2 integration step (s)", NULL},
    {"--tmax", CLI_OPT_NUM, &A.opts[IGEA_IMPACT_OPT_TMAX], CLI_DEF_LIB, "S", "longest flight searched (s)", NULL},
    CLI_HEAD("or the burnout from a trajectory (instead of --burnout and --errors):"),
    CLI_BURNOUT_OPTIONS(A.bo, "with --terms the burnout errors of the terms\n"
                        "there: the budget"),
    {"--terms", CLI_OPT_STR, &A.terms, NULL, "LIST", "the error terms of the budget: names, 'default'\n"
     "(the 21-term model) or 'all' (see igea envfun --list)", NULL},
    {"--spec", CLI_OPT_STR, &A.spec, "default", "default|FILE", "their 1-sigma specs: the catalogue's, or a file of\none per term", &A.given_spec},
    CLI_HEAD("error budget:"),
    {"--errors", CLI_OPT_STR, &A.errors, NULL, "FILE", "6 rows (x y z vx vy vz) by n columns: the burnout\n"
     "state error of each independent term at 1 sigma", NULL},
    {"--names", CLI_OPT_STR, &A.names, NULL, "LIST", "names of the n terms (default term_0, ...)", NULL},
    {"--prob", CLI_OPT_NUM, &A.prob, "0.5", "P", "probability of the circle (0.5: the CEP)", &A.given_prob},
    {"--plot", CLI_OPT_STR, &A.plot, NULL, "FILE.svg", "draw the budget: the impact plane with the 1 and 3\nsigma ellipses and the circle of --prob, and each\nterm's share as bars, into an SVG picture", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    CLI_END};

static const cli_command command = {"impact",
"usage: igea impact --burnout X,Y,Z,VX,VY,VZ [options]\n"
"       igea impact --burnout-time T --traj FILE --lat DEG --lon DEG --azimuth DEG\n"
"                   [--terms LIST] [options]\n"
"\n"
"The impact point of the ballistic free flight from a burnout state given in\n"
"Earth-fixed axes (ECEF, z the rotation axis), on the sphere of --radius:\n"
"the Kepler ellipse in closed form, or J2 integrated; the time of flight;\n"
"the derivatives of the impact with respect to the burnout state; the miss\n"
"along the downrange axis (the horizontal impact velocity) and the\n"
"crossrange axis (to its right) per unit of burnout error. With --errors,\n"
"the miss of each error term, each term's share of the impact covariance,\n"
"and the radius holding --prob of the impacts (exact, and the usual\n"
"approximations). With --burnout-time, the burnout state is the nav core's\n"
"navigation of the trajectory from the launch point at T s, and the errors of\n"
"--terms at --spec are their gravity-coupled position and velocity environment\n"
"functions there, in ECEF (igea_impact_burnout).\n"
"\n"
"options:\n",
options,
"\n"
"example (a burnout 150 km up at 30 N 10 E, 6 km/s):\n"
"  igea impact --burnout 5561563.2,980653.6,3260504.4,-495.5,3461.9,4875.4\n"
"  igea impact --burnout b.txt --model j2 --errors E.txt --names acc_bias_x,gyro_bias_y --json\n"
"the budget of the 21-term model at 100 s of a simulated flight:\n"
"  mkdir -p flight && igea simulate --dir flight --save-traj\n"
"  igea impact --burnout-time 100 --traj flight/traj.txt --lat 40.96 --lon 100.29 \\\n"
"      --height 1000 --azimuth 30 --terms default\n"};

/* The six numbers of --burnout: a comma list or a file. */
static int read_burnout(const char *arg, double *s)
{
    if (!strchr(arg, ',')) {
        double *v;
        int ec = cli_read_vector(arg, 6, "the burnout state (x y z vx vy vz)", &v, NULL);
        if (!ec)
            memcpy(s, v, 6 * sizeof(double)), free(v);
        return ec;
    }
    char **items;
    int n, ec = cli_split_list(arg, &items, &n);
    if (ec)
        return ec;
    if (n != 6) {
        cli_error("--burnout: %d numbers; six are needed (x,y,z,vx,vy,vz)", n);
        ec = CLI_USAGE;
    }
    for (int i = 0; i < n && !ec; i++)
        ec = cli_parse_double("--burnout", items[i], &s[i]);
    free(items);
    return ec;
}

typedef struct {
    double s[6], rf[3], vf[3], tf, jac[IGEA_IMPACT_JAC_ROWS * 6], down[3], cross[3], G[12];
    int n;
    double *E, *miss, cov[4], *share, radius, cep_sum, cep_rms;
    char **names;
} im_run;

/* The burnout state and, with --terms, the errors of the terms from the
 * trajectory (their names name the columns). */
static int from_traj(const im_args *a, im_run *r)
{
    int *codes = NULL, ec = CLI_OK;
    double *spec = NULL;
    if (a->terms && (!(ec = cli_parse_terms(a->bo.system, a->terms, &codes, &r->n)) &&
                     !(ec = cli_term_specs(a->bo.system, codes, r->n, a->spec, &spec)) &&
                     (!(r->E = malloc(sizeof(double) * 6 * (size_t)r->n)) ||
                      !(r->names = malloc(sizeof(char *) * (size_t)r->n)))))
        ec = cli_oom("the burnout errors");
    for (int j = 0; !ec && j < r->n; j++)
        r->names[j] = (char *)igea_envfun_term_name(codes[j]);
    if (!ec)
        ec = cli_burnout_compute(&a->bo, r->n, codes, spec, r->s, r->E);
    free(codes);
    free(spec);
    return ec;
}

static int budget(const im_args *a, im_run *r)
{
    int rows = 6, ec = a->errors ? cli_read_colmajor(a->errors, &r->E, &rows, &r->n) : CLI_OK;
    if (ec)
        return ec;
    if (rows != 6) {
        cli_error("%s: %d rows; the burnout errors are 6 rows (x y z vx vy vz) by one column "
                  "per term", a->errors, rows);
        return CLI_DATAERR;
    }
    if (a->names && a->errors) {
        int nn;
        if ((ec = cli_split_list(a->names, &r->names, &nn)))
            return ec;
        if (nn != r->n) {
            cli_error("--names: %d names for the %d columns of %s", nn, r->n, a->errors);
            return CLI_USAGE;
        }
    }
    if (!(r->miss = malloc(sizeof(double) * 3 * (size_t)r->n)))
        return cli_oom("the budget");
    r->share = r->miss + 2 * (size_t)r->n;
    int st = igea_impact_budget(r->n, r->G, 2, r->E, 6, r->miss, r->cov, r->share);
    if (!st)
        st = igea_impact_cep(r->cov, a->prob, &r->radius);
    if (!st)
        st = igea_impact_cep_approx(r->cov, IGEA_IMPACT_CEP_SUM, &r->cep_sum);
    if (!st)
        st = igea_impact_cep_approx(r->cov, IGEA_IMPACT_CEP_RMS, &r->cep_rms);
    return cli_status(st, "impact: the budget");
}

static int compute(const im_args *a, im_run *r)
{
    int st = igea_impact_point(a->model, a->opts, r->s, r->s + 3, r->rf, r->vf, &r->tf, r->jac,
                               IGEA_IMPACT_JAC_ROWS);
    if (st == IGEA_EDOMAIN) {
        cli_error("impact: the flight from this burnout does not come down to the sphere of "
                  "radius %g m (an orbit, an escape, a vertical flight or a burnout below it)",
                  a->opts[IGEA_IMPACT_OPT_RADIUS]);
        return CLI_DATAERR;
    }
    if (!st)
        st = igea_impact_axes(r->rf, r->vf, r->down, r->cross);
    if (!st)
        st = igea_impact_miss_jacobian(r->jac, IGEA_IMPACT_JAC_ROWS, r->rf, r->vf, r->G, 2);
    int ec = cli_status(st, "impact");
    return !ec && (a->errors || r->E) ? budget(a, r) : ec;
}

static const char *term_name(const im_run *r, int j, char *buf, size_t size)
{
    if (r->names)
        return r->names[j];
    snprintf(buf, size, "term_%d", j);
    return buf;
}

static void json_report(FILE *f, const im_args *a, const im_run *r)
{
    cli_json j;
    cli_json_begin(&j, f);
    cli_jstr(&j, "model", igea_choice_name(IGEA_CHOICE_IMPACT_MODEL, a->model));
    cli_jnums(&j, "burnout", r->s, 6);
    if (a->bo.given_time)
        cli_jnum(&j, "burnout_time", a->bo.time);
    cli_jnum(&j, "time", r->tf);
    cli_jnums(&j, "point", r->rf, 3);
    cli_jnums(&j, "velocity", r->vf, 3);
    cli_jnums(&j, "down", r->down, 3);
    cli_jnums(&j, "cross", r->cross, 3);
    cli_jmatrix(&j, "jacobian", r->jac, NULL, IGEA_IMPACT_JAC_ROWS, 6, 1, IGEA_IMPACT_JAC_ROWS);
    cli_jmatrix(&j, "miss_jacobian", r->G, NULL, 2, 6, 1, 2);
    if (r->E) {
        char buf[32];
        if (a->bo.given_time)
            cli_jmatrix(&j, "burnout_errors", r->E, NULL, 6, r->n, 1, 6);
        cli_json_open(&j, "names", '[');
        for (int k = 0; k < r->n; k++)
            cli_jstr(&j, NULL, term_name(r, k, buf, sizeof buf));
        cli_json_close(&j);
        cli_jrows(&j, "miss", r->miss, r->n, 2);
        cli_jnums(&j, "share", r->share, r->n);
        cli_jmatrix(&j, "covariance", r->cov, NULL, 2, 2, 1, 2);
        cli_jnum(&j, "prob", a->prob);
        cli_jnum(&j, "cep", r->radius);
        cli_jnum(&j, "cep_sum", r->cep_sum);
        cli_jnum(&j, "cep_rms", r->cep_rms);
    }
    cli_json_end(&j);
}

static void text_budget(FILE *f, const im_args *a, const im_run *r)
{
    char buf[32];
    fprintf(f, "\n%-20s %14s %14s %8s\n", "term", "downrange (m)", "crossrange (m)", "share");
    for (int k = 0; k < r->n; k++)
        fprintf(f, "%-20s %14.6g %14.6g %7.2f%%\n", term_name(r, k, buf, sizeof buf),
                r->miss[2 * k], r->miss[2 * k + 1], 100.0 * r->share[k]);
    fprintf(f, "impact covariance (m^2): [%.6g %.6g; %.6g %.6g]\n", r->cov[0], r->cov[2],
            r->cov[1], r->cov[3]);
    fprintf(f, "radius holding %g of the impacts: %.6g m (exact)", a->prob, r->radius);
    if (a->prob == 0.5)
        fprintf(f, "; approximations 0.5887 (s1 + s2) %.6g m, 1.1774 rms %.6g m", r->cep_sum,
                r->cep_rms);
    fprintf(f, "\n");
}

static void text_report(FILE *f, const im_args *a, const im_run *r)
{
    static const char *const col[6] = {"x", "y", "z", "vx", "vy", "vz"};
    if (a->bo.given_time)
        fprintf(f, "burnout at %g s of %s (ECEF): %.3f %.3f %.3f m, %.4f %.4f %.4f m/s\n",
                a->bo.time, a->bo.traj, r->s[0], r->s[1], r->s[2], r->s[3], r->s[4], r->s[5]);
    fprintf(f, "impact (%s): time of flight %.6f s\n",
            igea_choice_name(IGEA_CHOICE_IMPACT_MODEL, a->model), r->tf);
    fprintf(f, "point    %18.6f %18.6f %18.6f m (ECEF)\n", r->rf[0], r->rf[1], r->rf[2]);
    fprintf(f, "velocity %18.6f %18.6f %18.6f m/s\n", r->vf[0], r->vf[1], r->vf[2]);
    fprintf(f, "\nmiss per unit burnout error (m/m, m/(m/s))\n%-11s", "");
    for (int k = 0; k < 6; k++)
        fprintf(f, " %12s", col[k]);
    for (int i = 0; i < 2; i++) {
        fprintf(f, "\n%-11s", i ? "crossrange" : "downrange");
        for (int k = 0; k < 6; k++)
            fprintf(f, " %12.6g", r->G[i + 2 * k]);
    }
    fprintf(f, "\n");
    if (r->E)
        text_budget(f, a, r);
}

int cmd_impact(int argc, char **argv)
{
    igea_impact_defaults(A.opts);
    int ec = cli_parse(&command, argc, argv);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    im_args a = A;
    if (!a.burnout == !a.bo.given_time)
        return cli_usage("impact: --burnout or --burnout-time is required, not both (see igea "
                         "impact --help)");
    if ((ec = cli_burnout_check("impact", &a.bo)))
        return ec;
    if (a.bo.given_time && a.errors)
        return cli_usage("impact: --errors and --burnout-time are alternatives (--terms gives "
                         "the errors there)");
    if (!a.terms && a.given_spec)
        return cli_usage("impact: --spec needs --terms (the specs of the budget's terms)");
    if (!a.bo.given_time && a.terms)
        return cli_usage("impact: --terms needs --burnout-time (the burnout from a trajectory)");
    if (a.terms && a.names)
        return cli_usage("impact: --names: the --terms name the budget's columns");
    if (a.names && !a.errors)
        return cli_usage("impact: --names names the columns of --errors");
    if (a.given_prob && !a.errors && !a.terms)
        return cli_usage("impact: --prob is of the budget (--errors, or --terms with "
                         "--burnout-time)");
    if (a.plot && !a.errors && !a.terms)
        return cli_usage("impact: --plot draws the budget: it needs --errors, or --terms with "
                         "--burnout-time");
    if (!(a.prob > 0 && a.prob < 1))
        return cli_usage("impact: --prob must lie in (0, 1)");
    if ((ec = cli_check_opts("impact", IGEA_MODULE_IMPACT, igea_impact_check_opts(a.opts))))
        return ec;
    im_run r;
    memset(&r, 0, sizeof r);
    ec = a.bo.given_time ? from_traj(&a, &r) : read_burnout(a.burnout, r.s);
    if (!ec && !(ec = compute(&a, &r)) && a.plot) /* the picture first: on its failure no report */
        ec = cli_svg_impact(a.plot, r.n, r.names, r.miss, r.share, r.cov, a.prob, r.radius);
    if (!ec) {
        cli_out o;
        if (!(ec = cli_out_open(&o, a.out))) {
            (a.json ? json_report : text_report)(o.f, &a, &r);
            ec = cli_out_commit(&o);
        }
    }
    free(r.E);
    free(r.miss);
    free(r.names);
    return ec;
}
