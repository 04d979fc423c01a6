/* redund_group.c - virtual IMUs: groups of single-axis sensors, each
 * group's frame from its calibrated axes, unified into group 0's frame,
 * and the fused output with the covariance that counts shared sensors once
 * (include/igea/redund.h, docs/redundancy.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "igea/redund.h"
#include "igea/stability.h"
#include "internal.h"

/* 3 x 3 row-major inverse by cofactors; 1 when |det| <= 1e-12 times the
 * product of the row norms (the rows nearly dependent). */
static int inv3(const double *a, double *b)
{
    double c[9] = {a[4] * a[8] - a[5] * a[7], a[2] * a[7] - a[1] * a[8], a[1] * a[5] - a[2] * a[4],
                   a[5] * a[6] - a[3] * a[8], a[0] * a[8] - a[2] * a[6], a[2] * a[3] - a[0] * a[5],
                   a[3] * a[7] - a[4] * a[6], a[1] * a[6] - a[0] * a[7], a[0] * a[4] - a[1] * a[3]};
    double det = a[0] * c[0] + a[1] * c[3] + a[2] * c[6], nr = 1.0;
    for (int i = 0; i < 3; i++)
        nr *= sqrt(a[3 * i] * a[3 * i] + a[3 * i + 1] * a[3 * i + 1] + a[3 * i + 2] * a[3 * i + 2]);
    if (!(fabs(det) > 1e-12 * nr))
        return 1;
    for (int i = 0; i < 9; i++)
        b[i] = c[i] / det;
    return 0;
}

/* F (rows x y z in R) of the triad with axes rows A (row-major). */
static void triad_frame(const double *A, double *F)
{
    double nx = sqrt(A[0] * A[0] + A[1] * A[1] + A[2] * A[2]), d = 0.0, ny = 0.0;
    for (int j = 0; j < 3; j++)
        F[j] = A[j] / nx;
    for (int j = 0; j < 3; j++)
        d += A[3 + j] * F[j];
    for (int j = 0; j < 3; j++)
        F[3 + j] = A[3 + j] - d * F[j], ny += F[3 + j] * F[3 + j];
    for (int j = 0; j < 3; j++)
        F[3 + j] /= sqrt(ny);
    F[6] = F[1] * F[5] - F[2] * F[4];
    F[7] = F[2] * F[3] - F[0] * F[5];
    F[8] = F[0] * F[4] - F[1] * F[3];
}

static int check_args(int nsens, const double *axes, const double *sigma, int ngroup,
                      const int *member, const double *y, int fusion, const double *fused,
                      const double *cov)
{
    if (nsens < 3)
        return -1;
    if (!axes)
        return -2;
    if (!sigma)
        return -3;
    if (ngroup < 1)
        return -4;
    if (!member)
        return -5;
    for (int g = 0; g < ngroup; g++)
        for (int k = 0; k < 3; k++) {
            int m = member[3 * g + k];
            if (m < 0 || m >= nsens || (k > 0 && m == member[3 * g]) ||
                (k == 2 && m == member[3 * g + 1]))
                return -5;
        }
    if (!y)
        return -6;
    if (fusion < IGEA_REDUND_GROUP_AVERAGE || fusion > IGEA_REDUND_GROUP_GLS)
        return -7;
    if (!fused)
        return -10;
    if (!cov)
        return -11;
    if (!igea__finite_mat(3, nsens, axes, 3) || !igea__finite_vec(nsens, y, 1))
        return IGEA_ENONFINITE;
    return igea__sigma_vec(nsens, sigma);
}

/* G (3 x nsens row-major, zero outside the group's columns) = F_0 A_g^-1
 * and C_g = F_0 F_g^T (row-major); 1 for a singular triad. */
static int group_map(int nsens, const double *axes, const int *mem, const double *F0,
                     double *G, double *Cg)
{
    double A[9], Ai[9], F[9];
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            A[3 * k + j] = axes[3 * mem[k] + j];
    if (inv3(A, Ai))
        return 1;
    triad_frame(A, F);
    memset(G, 0, sizeof(double) * 3 * (size_t)nsens);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            double s = 0.0, c = 0.0;
            for (int j = 0; j < 3; j++)
                s += F0[3 * i + j] * Ai[3 * j + k], c += F0[3 * i + j] * F[3 * k + j];
            G[(size_t)i * nsens + mem[k]] += s;
            Cg[3 * i + k] = c;
        }
    return 0;
}

/* out (3 x 3) = M diag(sigma^2) M^T, M 3 x nsens row-major */
static void sandwich(int nsens, const double *M, const double *sigma, double *out)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0.0;
            for (int k = 0; k < nsens; k++)
                s += M[(size_t)i * nsens + k] * M[(size_t)j * nsens + k] * sigma[k] * sigma[k];
            out[3 * i + j] = s;
        }
}

/* L of the GLS of the distinct sensors used (union of the groups), body
 * axes a'_s = F_0 a_s: L[:, s] = N^-1 a'_s / sigma_s^2. */
static int gls_map(int nsens, const double *axes, const double *sigma, const int *used,
                   const double *F0, double *L)
{
    double N[9] = {0}, Ni[9];
    double *b = igea__dalloc(3 * (size_t)nsens);
    if (!b)
        return IGEA_ENOMEM;
    for (int s = 0; s < nsens; s++)
        for (int i = 0; i < 3; i++) {
            b[3 * s + i] = 0.0;
            for (int j = 0; j < 3; j++)
                b[3 * s + i] += F0[3 * i + j] * axes[3 * s + j];
        }
    for (int s = 0; s < nsens; s++)
        for (int i = 0; i < 3 && used[s]; i++)
            for (int j = 0; j < 3; j++)
                N[3 * i + j] += b[3 * s + i] * b[3 * s + j] / (sigma[s] * sigma[s]);
    int st = inv3(N, Ni) ? IGEA_ESINGULAR : 0;
    for (int s = 0; s < nsens && !st; s++)
        for (int i = 0; i < 3; i++) {
            double v = 0.0;
            for (int j = 0; j < 3; j++)
                v += Ni[3 * i + j] * b[3 * s + j];
            L[(size_t)i * nsens + s] = used[s] ? v / (sigma[s] * sigma[s]) : 0.0;
        }
    free(b);
    return st;
}

/* The fusion weights of the group outputs W (ngroup x 3: weight of group
 * g on body axis i) and L = sum_g diag(W_g) G_g. */
static void combine(int nsens, int ngroup, const double *G, const double *sigma, int fusion,
                    double *W, double *L)
{
    size_t n3 = 3 * (size_t)nsens;
    for (int i = 0; i < 3; i++) {
        double tot = 0.0;
        for (int g = 0; g < ngroup; g++) {
            double v = 0.0;
            for (int k = 0; k < nsens; k++) {
                double e = G[g * n3 + (size_t)i * nsens + k] * sigma[k];
                v += e * e;
            }
            W[3 * g + i] = fusion == IGEA_REDUND_GROUP_WEIGHTED ? 1.0 / v : 1.0;
            tot += W[3 * g + i];
        }
        for (int g = 0; g < ngroup; g++)
            W[3 * g + i] /= tot;
    }
    memset(L, 0, sizeof(double) * n3);
    for (int g = 0; g < ngroup; g++)
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < nsens; k++)
                L[(size_t)i * nsens + k] += W[3 * g + i] * G[g * n3 + (size_t)i * nsens + k];
}

/* cov_indep = sum_g diag(W_g) Cov(u_g) diag(W_g). */
static void indep_cov(int nsens, int ngroup, const double *G, const double *sigma,
                      const double *W, double *out)
{
    double c[9];
    memset(out, 0, 9 * sizeof *out);
    for (int g = 0; g < ngroup; g++) {
        sandwich(nsens, G + (size_t)g * 3 * nsens, sigma, c);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                out[3 * i + j] += W[3 * g + i] * c[3 * i + j] * W[3 * g + j];
    }
}

static void store(int nsens, int ngroup, const double *G, const double *C, const double *L,
                  const double *y, const double *sigma, double *frames, double *group_out,
                  double *fused, double *cov)
{
    for (int g = 0; g < ngroup; g++)
        for (int i = 0; i < 3; i++) {
            double u = 0.0;
            for (int k = 0; k < nsens; k++)
                u += G[((size_t)g * 3 + i) * nsens + k] * y[k];
            if (group_out)
                group_out[3 * g + i] = u;
            for (int j = 0; j < 3 && frames; j++)
                frames[9 * g + 3 * j + i] = C[9 * g + 3 * i + j]; /* column-major */
        }
    double c[9];
    for (int i = 0; i < 3; i++) {
        fused[i] = 0.0;
        for (int k = 0; k < nsens; k++)
            fused[i] += L[(size_t)i * nsens + k] * y[k];
    }
    sandwich(nsens, L, sigma, c);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            cov[3 * j + i] = c[3 * i + j];
}

int igea_redund_group(int nsens, const double *axes, const double *sigma, int ngroup,
                      const int *member, const double *y, int fusion, double *frames,
                      double *group_out, double *fused, double *cov, double *cov_indep)
{
    int st = check_args(nsens, axes, sigma, ngroup, member, y, fusion, fused, cov);
    if (st)
        return st;
    size_t n3 = 3 * (size_t)nsens;
    double *G = igea__dalloc((size_t)ngroup * n3 + n3), *C = igea__dalloc(9 * (size_t)ngroup);
    double *W = igea__dalloc(3 * (size_t)ngroup);
    int *used = igea__ialloc((size_t)nsens);
    if (!G || !C || !W || !used) {
        st = IGEA_ENOMEM;
        goto done;
    }
    double A0[9], F0[9], *L = G + (size_t)ngroup * n3, ci[9];
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            A0[3 * k + j] = axes[3 * member[k] + j];
    triad_frame(A0, F0);
    memset(used, 0, sizeof(int) * (size_t)nsens);
    for (int g = 0; g < ngroup && !st; g++) {
        if (group_map(nsens, axes, member + 3 * g, F0, G + (size_t)g * n3, C + 9 * g))
            st = IGEA_ESINGULAR;
        for (int k = 0; k < 3; k++)
            used[member[3 * g + k]] = 1;
    }
    if (st)
        goto done;
    if (fusion == IGEA_REDUND_GROUP_GLS)
        st = gls_map(nsens, axes, sigma, used, F0, L);
    else
        combine(nsens, ngroup, G, sigma, fusion, W, L);
    if (st)
        goto done;
    if (fusion == IGEA_REDUND_GROUP_GLS)
        sandwich(nsens, L, sigma, ci);
    else
        indep_cov(nsens, ngroup, G, sigma, W, ci);
    store(nsens, ngroup, G, C, L, y, sigma, frames, group_out, fused, cov);
    if (cov_indep)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                cov_indep[3 * j + i] = ci[3 * i + j];
done:
    free(G);
    free(C);
    free(W);
    free(used);
    return st;
}

/* ---- Table 1: block statistics per sensor and per fused channel -------- */

static int stab_args(int nsamp, int nsens, const double *y, int ldy, double fs, double block,
                     const int *channel, int nchan, int weighted)
{
    if (nsamp < 2)
        return -1;
    if (nsens < 1)
        return -2;
    if (!y)
        return -3;
    if (ldy < nsamp)
        return -4;
    if (!(fs > 0) || !isfinite(fs))
        return -5;
    if (!(block > 0) || !isfinite(block) || !(floor(block * fs + 0.5) >= 1) ||
        !(floor(nsamp / floor(block * fs + 0.5)) >= 2))
        return -6;
    if (!channel)
        return -7;
    if (nchan < 1)
        return -8;
    for (int i = 0; i < nsens; i++)
        if (channel[i] < -1 || channel[i] >= nchan)
            return -7;
    for (int c = 0; c < nchan; c++) {
        int any = 0;
        for (int i = 0; i < nsens; i++)
            any |= channel[i] == c;
        if (!any)
            return -8;
    }
    if (weighted != 0 && weighted != 1)
        return -9;
    return igea__finite_mat(nsamp, nsens, y, ldy) ? 0 : IGEA_ENONFINITE;
}

int igea_redund_stability(int nsamp, int nsens, const double *y, int ldy, double fs,
                          double block, const int *channel, int nchan, int weighted,
                          double *sens_out, double *fused_out, double *fused)
{
    int st = stab_args(nsamp, nsens, y, ldy, fs, block, channel, nchan, weighted);
    if (st)
        return st;
    if (!sens_out)
        return -10;
    if (!fused_out)
        return -11;
    const int L = IGEA_STABILITY_BLOCK_LEN;
    double *so = igea__dalloc((size_t)L * nsens), *fo = igea__dalloc((size_t)L * nchan);
    double *fs_ = igea__dalloc((size_t)nsamp * nchan), *w = igea__dalloc((size_t)nsens);
    if (!so || !fo || !fs_ || !w) {
        st = IGEA_ENOMEM;
        goto done;
    }
    for (int i = 0; i < nsens && !st; i++)
        st = igea_stability_block(nsamp, y + (size_t)i * ldy, fs, block, so + (size_t)L * i);
    for (int i = 0; i < nsens && !st; i++) {
        double sb = so[(size_t)L * i + IGEA_STABILITY_BLOCK_SIGMA];
        if (weighted && channel[i] >= 0 && !(sb > 0))
            st = IGEA_EDOMAIN;
        w[i] = weighted ? 1.0 / (sb * sb) : 1.0;
    }
    for (int c = 0; c < nchan && !st; c++) {
        double tot = 0.0, *col = fs_ + (size_t)c * nsamp;
        for (int i = 0; i < nsens; i++)
            tot += channel[i] == c ? w[i] : 0.0;
        for (int k = 0; k < nsamp; k++) {
            double s = 0.0;
            for (int i = 0; i < nsens; i++)
                if (channel[i] == c)
                    s += w[i] / tot * y[(size_t)i * ldy + k];
            col[k] = s;
        }
        st = igea_stability_block(nsamp, col, fs, block, fo + (size_t)L * c);
    }
    if (!st) {
        memcpy(sens_out, so, sizeof(double) * L * (size_t)nsens);
        memcpy(fused_out, fo, sizeof(double) * L * (size_t)nchan);
        if (fused)
            memcpy(fused, fs_, sizeof(double) * (size_t)nsamp * nchan);
    }
done:
    free(so);
    free(fo);
    free(fs_);
    free(w);
    return st;
}
