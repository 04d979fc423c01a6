/* sim_noise.c - the simulator's noise models beyond white: AR(p) per axis
 * (p <= 3, exact stationary start), a per-epoch 3 x 3 correlation, two
 * groups with their own sigma_w and bias (IGEA_SIM_OPT_AR2 .. JUDGE_NOISE),
 * and the Monte Carlo judge that states them to igea_noise_eqerr. */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "igea/noise.h"
#include "igea/sim.h"
#include "internal.h"
#include "sim_noise.h"

int igea__ar_setup(int p, const double *phi, double linv[][IGEA_NOISE_AR_MAX], double *su);

/* The AR order of the simulation options (highest nonzero lag). */
static int sim_ar_order(const double *o)
{
    return o[IGEA_SIM_OPT_AR3] != 0 ? 3 : o[IGEA_SIM_OPT_AR2] != 0 ? 2
                                          : o[IGEA_SIM_OPT_AR1] != 0 ? 1 : 0;
}

int igea__sim_noise_check(const double *o)
{
    int p = sim_ar_order(o);
    double phi[3] = {o[IGEA_SIM_OPT_AR1], o[IGEA_SIM_OPT_AR2], o[IGEA_SIM_OPT_AR3]};
    double li[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX], su;
    if (p > 1 && igea__ar_setup(p, phi, li, &su))
        return 1 + (p == 3 ? IGEA_SIM_OPT_AR3 : IGEA_SIM_OPT_AR2);
    if (!(fabs(o[IGEA_SIM_OPT_CORR]) < 1)) return 1 + IGEA_SIM_OPT_CORR;
    if (!(o[IGEA_SIM_OPT_GROUP_SPLIT] >= 0 && o[IGEA_SIM_OPT_GROUP_SPLIT] < 1)) return 1 + IGEA_SIM_OPT_GROUP_SPLIT;
    if (!(o[IGEA_SIM_OPT_SIGMA_W2] >= 0)) return 1 + IGEA_SIM_OPT_SIGMA_W2;
    if (o[IGEA_SIM_OPT_JUDGE_NOISE] != 0 && o[IGEA_SIM_OPT_JUDGE_NOISE] != 1) return 1 + IGEA_SIM_OPT_JUDGE_NOISE;
    return 0;
}

int igea__sim_noise_plain(const double *o)
{
    for (int k = IGEA_SIM_OPT_AR2; k <= IGEA_SIM_OPT_BIAS1; k++)
        if (o[k] != 0)
            return 0;
    return 1;
}

int igea__sim_group_of(const double *o, int M, int e)
{
    double s = o[IGEA_SIM_OPT_GROUP_SPLIT];
    return s > 0 && e >= s * M ? 1 : 0;
}

/* Cholesky factor (lower, row-major 3 x 3) of the epoch's correlation. */
void igea__sim_corr_chol(const double *o, int M, int e, double L[9])
{
    double r = o[IGEA_SIM_OPT_CORR] * (M > 1 ? e / (double)(M - 1) : 0.0), r2 = r * r;
    /* R = [[1 r r2][r 1 r][r2 r 1]] */
    double l10 = r, l11 = sqrt(1 - r * r);
    double l20 = r2, l21 = (r - r2 * r) / l11;
    double l22 = sqrt(fmax(1 - r2 * r2 - l21 * l21, 0.0));
    double v[9] = {1, 0, 0, l10, l11, 0, l20, l21, l22};
    memcpy(L, v, sizeof v);
}

/* Lower Cholesky factor L_p of Gamma_p from its inverse (row-major p x p). */
static void invert_lower(int p, double li[][IGEA_NOISE_AR_MAX], double L[][IGEA_NOISE_AR_MAX])
{
    for (int i = 0; i < p; i++)
        for (int j = 0; j <= i; j++) {
            double s = (i == j) ? 1.0 : 0.0;
            for (int l = j; l < i; l++)
                s -= li[i][l] * L[l][j];
            L[i][j] = s / li[i][i];
        }
}

/* Noise of a flight added to dw (m rows); draws per row as igea_sim_flight
 * documents (a normal, a uniform, a normal). */
void igea__sim_noise_rows(const double *o, const double *sigma, int m, gsl_rng *r,
                          double *dw)
{
    const int M = m / 3, p = sim_ar_order(o);
    double phi[3] = {o[IGEA_SIM_OPT_AR1], o[IGEA_SIM_OPT_AR2], o[IGEA_SIM_OPT_AR3]};
    double li[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX], Lp[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX];
    double su = 1.0, hist[3][3] = {{0}}, gh[3][3] = {{0}};
    if (p > 0) {
        igea__ar_setup(p, phi, li, &su);
        su = 1.0 / su; /* sigma_u */
        invert_lower(p, li, Lp);
    }
    double sw[2] = {o[IGEA_SIM_OPT_SIGMA_W],
                    o[IGEA_SIM_OPT_SIGMA_W2] > 0 ? o[IGEA_SIM_OPT_SIGMA_W2] : o[IGEA_SIM_OPT_SIGMA_W]};
    double bias[2] = {o[IGEA_SIM_OPT_BIAS0], o[IGEA_SIM_OPT_BIAS1]};
    int grp = -1, k = 0;
    for (int e = 0; e < M; e++) {
        int g = igea__sim_group_of(o, M, e);
        double eps[3], u[3], go[3], L[9];
        if (g != grp)
            grp = g, k = 0;
        for (int a = 0; a < 3; a++) {
            double z = gsl_ran_gaussian_ziggurat(r, 1.0);
            u[a] = gsl_rng_uniform(r);
            go[a] = gsl_ran_gaussian_ziggurat(r, 1.0);
            if (p == 0) {
                eps[a] = z;
            } else if (k < p) { /* exact stationary start: L_p times the normals */
                gh[a][k] = z;
                double s = 0.0;
                for (int l = 0; l <= k; l++)
                    s += Lp[k][l] * gh[a][l];
                eps[a] = s;
            } else {
                double s = su * z;
                for (int l = 0; l < p; l++)
                    s += phi[l] * hist[a][l];
                eps[a] = s;
            }
            for (int l = 2; l > 0; l--)
                hist[a][l] = hist[a][l - 1];
            hist[a][0] = eps[a];
        }
        igea__sim_corr_chol(o, M, e, L);
        double grow = 1.0 + (M > 1 ? o[IGEA_SIM_OPT_GROWTH] * e / (double)(M - 1) : 0.0);
        for (int a = 0; a < 3; a++) {
            int i = 3 * e + a;
            double sd = sw[g] * sigma[i] * grow;
            double n = L[3 * a] * eps[0] + L[3 * a + 1] * eps[1] + L[3 * a + 2] * eps[2];
            dw[i] += sd * n + bias[g] * sigma[i];
            if (u[a] < o[IGEA_SIM_OPT_OUTLIER_PROB])
                dw[i] += o[IGEA_SIM_OPT_OUTLIER_SCALE] * sd * go[a];
        }
        k++;
    }
}

int igea__sim_noise_judged(const double *so, const double *eqo)
{
    return so[IGEA_SIM_OPT_JUDGE_NOISE] == 1 || eqo[IGEA_EQERR_OPT_AR] != 0 ||
           eqo[IGEA_EQERR_OPT_ROBUST] != 0 || eqo[IGEA_EQERR_OPT_GROUP_BIAS] != 0;
}

int igea__sim_judge_stated(const double *so, const double *eqo, int m, const double *sigma,
                           double *cov, int *group, int *ngroups, double *phi)
{
    const int M = m / 3, told = so[IGEA_SIM_OPT_JUDGE_NOISE] == 1;
    const int usecov = told && so[IGEA_SIM_OPT_CORR] != 0;
    *ngroups = told && so[IGEA_SIM_OPT_GROUP_SPLIT] > 0 ? 2 : 1;
    for (int e = 0; e < M; e++) {
        group[e] = *ngroups > 1 ? igea__sim_group_of(so, M, e) : 0;
        if (!usecov)
            continue;
        double L[9], C[9];
        igea__sim_corr_chol(so, M, e, L);
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double s = 0.0;
                for (int l = 0; l < 3; l++)
                    s += L[3 * a + l] * L[3 * b + l];
                C[3 * a + b] = s * sigma[3 * e + a] * sigma[3 * e + b];
            }
        double *c6 = cov + 6 * (size_t)e;
        c6[0] = C[0], c6[1] = C[3], c6[2] = C[4], c6[3] = C[6], c6[4] = C[7], c6[5] = C[8];
    }
    int p = (int)eqo[IGEA_EQERR_OPT_AR];
    double tphi[3] = {so[IGEA_SIM_OPT_AR1], so[IGEA_SIM_OPT_AR2], so[IGEA_SIM_OPT_AR3]};
    for (int a = 0; a < 3; a++)
        for (int l = 0; l < p; l++)
            phi[a * p + l] = tphi[l];
    return usecov;
}
