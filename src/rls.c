/* rls.c - standard, iterated and polynomial recursive least squares with
 * anomaly handling (METHODS 2.1-2.8). All memory is allocated by
 * igea_rls_create; igea_rls_update never allocates. */
#include <float.h>

#include <cblas.h>

#include "igea/rls.h"
#include "internal.h"

#define RLS_MAX_P 1000000

struct igea_rls {
    int m, k;
    int variant, p, policy;
    double kappa, lambda;
    int has_jump;
    int p_same; /* 1 while P equals Gamma (every gain so far was K) */
    int since_sym; /* updates since the triangles were last mirrored */
    int track_cov; /* 1: P is tracked; 0: not (after a p > 1 gain, unknown) */
    int cov_valid; /* 0 once a p > 1 gain was used with tracking off */
    double *jump_max; /* k */
    double *x, *xn;            /* m */
    double *gam, *cov;         /* m x m, both triangles, ld m */
    double *ct, *gt, *ut;      /* m x k */
    /* m x 2k each: KB holds K, BK the Gamma downdate factor V, KPB the gain
     * K_p then [Z2 Z1], BKP [Z2 -Z1] (the P update, cov_prepare) */
    double *KB, *BK, *KPB, *BKP;
    double *A, *W, *Mk, *Mp, *Sm, *Jw; /* k x k */
    double *a, *yw, *e, *r, *yprev, *yused; /* k */
    int *yprev_ok, *keep, *fl; /* k */
    igea__ksum q;
    int counts[IGEA_RLS_COUNT_LEN];
    void *mem_d, *mem_i;
};

/* ---- small dense helpers --------------------------------------------- */

/* Cyclic Jacobi eigen-decomposition of the n x n symmetric a (full, ld n,
 * destroyed): w eigenvalues, v (ld n) eigenvectors as columns. */
static void jacobi_eig(int n, double *a, double *w, double *v)
{
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            v[i + (size_t)j * n] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 60 && n > 1; sweep++) {
        double off = 0.0, dia = 0.0;
        for (int j = 0; j < n; j++) {
            dia += a[j + (size_t)j * n] * a[j + (size_t)j * n];
            for (int i = j + 1; i < n; i++)
                off += a[i + (size_t)j * n] * a[i + (size_t)j * n];
        }
        if (off == 0.0 || off <= DBL_EPSILON * DBL_EPSILON * 1e-4 * dia)
            break;
        for (int pq = 0; pq < n - 1; pq++) {
            for (int qq = pq + 1; qq < n; qq++) {
                double apq = a[pq + (size_t)qq * n];
                double app = a[pq + (size_t)pq * n], aqq = a[qq + (size_t)qq * n];
                /* below rounding of both diagonal entries: negligible */
                double g = 100.0 * fabs(apq);
                if (fabs(app) + g == fabs(app) && fabs(aqq) + g == fabs(aqq))
                    a[pq + (size_t)qq * n] = a[qq + (size_t)pq * n] = apq = 0.0;
                if (apq == 0.0)
                    continue;
                double theta = (aqq - app) / (2.0 * apq);
                double t = (theta >= 0 ? 1.0 : -1.0) /
                           (fabs(theta) + sqrt(theta * theta + 1.0));
                if (!isfinite(theta * theta))
                    t = 1.0 / (2.0 * theta);
                double cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
                for (int r = 0; r < n; r++) { /* columns pq, qq */
                    double arp = a[r + (size_t)pq * n], arq = a[r + (size_t)qq * n];
                    a[r + (size_t)pq * n] = cs * arp - sn * arq;
                    a[r + (size_t)qq * n] = sn * arp + cs * arq;
                }
                for (int r = 0; r < n; r++) { /* rows pq, qq */
                    double apr = a[pq + (size_t)r * n], aqr = a[qq + (size_t)r * n];
                    a[pq + (size_t)r * n] = cs * apr - sn * aqr;
                    a[qq + (size_t)r * n] = sn * apr + cs * aqr;
                }
                a[pq + (size_t)qq * n] = a[qq + (size_t)pq * n] = 0.0;
                for (int r = 0; r < n; r++) {
                    double vrp = v[r + (size_t)pq * n], vrq = v[r + (size_t)qq * n];
                    v[r + (size_t)pq * n] = cs * vrp - sn * vrq;
                    v[r + (size_t)qq * n] = sn * vrp + cs * vrq;
                }
            }
        }
    }
    for (int j = 0; j < n; j++)
        w[j] = a[j + (size_t)j * n];
}

/* M = W diag(d) W^T, n x n (ld n). */
static void eig_func(int n, const double *W, const double *d, double *M)
{
    for (int j = 0; j < n; j++)
        for (int i = j; i < n; i++) {
            double s = 0.0;
            for (int l = 0; l < n; l++)
                s += W[i + (size_t)l * n] * d[l] * W[j + (size_t)l * n];
            M[i + (size_t)j * n] = M[j + (size_t)i * n] = s;
        }
}

/* f_p(a) = sum_{j=1..p} (1 + a)^-j = -expm1(-p log1p(a)) / a, f_p(0) = p. */
static double poly_gain(double a, int p)
{
    if (!(a > 0.0))
        return (double)p;
    return -expm1(-(double)p * log1p(a)) / a;
}

/* 1 if the n contiguous doubles are all finite (x * 0 is NaN exactly for
 * NaN and Inf; four independent sums keep the loop short). */
static int finite_block(size_t n, const double *x)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        s0 += x[i] * 0.0;
        s1 += x[i + 1] * 0.0;
        s2 += x[i + 2] * 0.0;
        s3 += x[i + 3] * 0.0;
    }
    for (; i < n; i++)
        s0 += x[i] * 0.0;
    return s0 + s1 + s2 + s3 == 0.0;
}

/* 1 if the rows x cols column-major matrix (ld) is finite. */
static int finite_strided(int rows, int cols, const double *a, size_t ld)
{
    if (ld == (size_t)rows)
        return finite_block((size_t)rows * (size_t)cols, a);
    for (int j = 0; j < cols; j++)
        if (!finite_block((size_t)rows, a + (size_t)j * ld))
            return 0;
    return 1;
}

/* ---- create / free / setters ---------------------------------------- */

/* A zeroed handle for m coefficients and k rows, every array in two
 * blocks (all the memory igea_rls_update will ever use); NULL when out of
 * memory. */
static igea_rls *rls_alloc(int m, int k)
{
    igea_rls *h = malloc(sizeof *h);
    if (!h)
        return NULL;
    memset(h, 0, sizeof *h);
    size_t M = (size_t)m, K = (size_t)k;
    size_t nd = 2 * M + 2 * M * M + 11 * M * K + 6 * K * K + 7 * K;
    h->mem_d = igea__dalloc(nd);
    h->mem_i = igea__ialloc(3 * K);
    if (!h->mem_d || !h->mem_i) {
        igea_rls_free(h);
        return NULL;
    }
    double *d = h->mem_d;
    h->x = d; d += M;
    h->xn = d; d += M;
    h->gam = d; d += M * M;
    h->cov = d; d += M * M;
    h->ct = d; d += M * K;
    h->gt = d; d += M * K;
    h->ut = d; d += M * K;
    h->KB = d; d += 2 * M * K;
    h->BK = d; d += 2 * M * K;
    h->KPB = d; d += 2 * M * K;
    h->BKP = d; d += 2 * M * K;
    h->A = d; d += K * K;
    h->W = d; d += K * K;
    h->Mk = d; d += K * K;
    h->Mp = d; d += K * K;
    h->Sm = d; d += K * K;
    h->Jw = d; d += K * K;
    h->a = d; d += K;
    h->yw = d; d += K;
    h->e = d; d += K;
    h->r = d; d += K;
    h->yprev = d; d += K;
    h->yused = d; d += K;
    h->jump_max = d;
    h->yprev_ok = h->mem_i;
    h->keep = h->yprev_ok + K;
    h->fl = h->keep + K;
    memset(h->mem_d, 0, nd * sizeof(double));
    return h;
}

int igea_rls_create(int m, int k, const double *x0, const double *gamma0,
                    int ldg, igea_rls **out)
{
    if (out)
        *out = NULL;
    if (m < 1)
        return -1;
    if (k < 1)
        return -2;
    if (!gamma0)
        return -4;
    if (ldg < m)
        return -5;
    if (!out)
        return -6;
    if (x0 && !igea__finite_vec(m, x0, 1))
        return IGEA_ENONFINITE;
    for (int j = 0; j < m; j++)
        for (int i = j; i < m; i++)
            if (!isfinite(IGEA_AT(gamma0, ldg, i, j)))
                return IGEA_ENONFINITE;

    igea_rls *h = rls_alloc(m, k);
    if (!h)
        return IGEA_ENOMEM;
    size_t M = (size_t)m;

    /* Positive definiteness of Gamma_0: Cholesky of a copy in cov (P is
     * only read once it has been set from Gamma). */
    double *L = h->cov;
    for (int j = 0; j < m; j++)
        for (int i = j; i < m; i++)
            L[i + M * j] = IGEA_AT(gamma0, ldg, i, j);
    if (igea__chol_lower(m, L, m, 0.0) != 0) {
        igea_rls_free(h);
        return IGEA_ESINGULAR;
    }
    for (int j = 0; j < m; j++)
        for (int i = j; i < m; i++)
            h->gam[i + M * j] = h->gam[j + M * i] = IGEA_AT(gamma0, ldg, i, j);
    if (x0)
        memcpy(h->x, x0, M * sizeof(double));
    h->m = m;
    h->k = k;
    h->variant = IGEA_RLS_STANDARD;
    h->p = 1;
    h->policy = IGEA_RLS_ANOMALY_NONE;
    h->kappa = 4.0;
    h->lambda = 1.0;
    h->has_jump = 0;
    h->p_same = 1;
    h->track_cov = 1;
    h->cov_valid = 1;
    for (int j = 0; j < k; j++) {
        h->jump_max[j] = INFINITY;
        h->yprev_ok[j] = 0;
    }
    *out = h;
    return 0;
}

void igea_rls_free(igea_rls *h)
{
    if (!h)
        return;
    free(h->mem_d);
    free(h->mem_i);
    free(h);
}

int igea_rls_set_variant(igea_rls *h, int variant, int p)
{
    if (!h)
        return -1;
    if (variant != IGEA_RLS_STANDARD && variant != IGEA_RLS_ITERATED &&
        variant != IGEA_RLS_POLYNOMIAL)
        return -2;
    if (p < 1 || p > RLS_MAX_P)
        return -3;
    h->variant = variant;
    h->p = variant == IGEA_RLS_STANDARD ? 1 : p;
    return 0;
}

int igea_rls_set_anomaly(igea_rls *h, int policy, double kappa,
                         const double *jump_max)
{
    if (!h)
        return -1;
    if (policy < IGEA_RLS_ANOMALY_NONE || policy > IGEA_RLS_ANOMALY_ISOLATE)
        return -2;
    if (!(kappa > 0.0)) /* NaN fails too; +Inf allowed (test off) */
        return -3;
    if (jump_max)
        for (int j = 0; j < h->k; j++)
            if (!(jump_max[j] > 0.0))
                return -4;
    h->policy = policy;
    h->kappa = kappa;
    h->has_jump = 0;
    for (int j = 0; j < h->k; j++) {
        h->jump_max[j] = jump_max ? jump_max[j] : INFINITY;
        if (isfinite(h->jump_max[j]))
            h->has_jump = 1;
    }
    return 0;
}

int igea_rls_set_covariance(igea_rls *h, int track)
{
    if (!h)
        return -1;
    if (track != 0 && track != 1)
        return -2;
    if (h->counts[IGEA_RLS_COUNT_EPOCHS] > 0)
        return IGEA_EDOMAIN;
    h->track_cov = track;
    return 0;
}

int igea_rls_set_forget(igea_rls *h, double lambda)
{
    if (!h)
        return -1;
    if (!(lambda > 0.0 && lambda <= 1.0))
        return -2;
    h->lambda = lambda;
    return 0;
}

/* ---- the update ------------------------------------------------------- */

/* Residuals r = yw - ct^T x over kk rows. */
static void resid(int m, int kk, const double *ct, const double *yw,
                  const double *x, double *r)
{
    for (int j = 0; j < kk; j++)
        r[j] = yw[j];
    cblas_dgemv(CblasColMajor, CblasTrans, m, kk, -1.0, ct, m, x, 1, 1.0, r, 1);
}

/* y += f x and x *= f over n contiguous doubles (no aliasing). */
static void axpy(int n, double f, const double *restrict x, double *restrict y)
{
    cblas_daxpy(n, f, x, 1, y, 1);
}

static void scal(int n, double f, double *restrict x)
{
    cblas_dscal(n, f, x, 1);
}

/* S = (ct^T ut + ut^T ct) / 2, kk x kk: symmetric by construction. */
static void small_sym(int m, int kk, const double *ct, const double *ut, double *S)
{
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, kk, kk, m, 1.0, ct, m, ut, m,
                0.0, S, kk);
    for (int j = 0; j < kk; j++)
        for (int i = j + 1; i < kk; i++)
            S[i + (size_t)j * kk] = S[j + (size_t)i * kk] =
                0.5 * (S[i + (size_t)j * kk] + S[j + (size_t)i * kk]);
}

/* Mirror the lower triangle of the m x m matrix g onto the upper one. */
static void mirror(int m, double *g)
{
    for (int j = 0; j < m; j++)
        for (int i = j + 1; i < m; i++)
            g[j + (size_t)i * m] = g[i + (size_t)j * m];
}

/* Prepare the honest-covariance update (METHODS 2.4) of the symmetric src
 * (full, ld m) with the gain G (m x kk), in factored form:
 *   (I - G c) P (I - G c)^T + G G^T  (P = src/lambda)
 *     = P - Z1 Z1^T + Z2 Z2^T,
 *   M = I + c P c^T = L L^T (Cholesky, kk x kk),  U^T = P c^T (ut),
 *   Z1 = U^T L^-T                  (the optimal-gain downdate),
 *   Z2 = (G - U^T M^-1) L          (the excess of the gain used),
 * applied as src/lambda + [Z2 Z1] [Z2 -Z1]^T, one dgemm of inner size 2kk,
 * symmetric bit for bit and robust for diffuse priors (the Joseph form
 * expanded as sums cancels catastrophically there). Writes GB = [Z2 Z1],
 * BG = [Z2 -Z1] (m x 2kk each). Returns 0 if the new diagonal is positive
 * and finite, else IGEA_ESINGULAR / IGEA_ENONFINITE. */
static int cov_prepare(igea_rls *h, int kk, double linv, const double *src,
                       const double *ut, const double *G, double *GB, double *BG)
{
    const int m = h->m;
    const size_t mk = (size_t)m * kk, M = (size_t)m;
    double *Z2 = GB, *Z1 = GB + mk, *T = BG, *L = h->Sm;
    small_sym(m, kk, h->ct, ut, L);
    int st = igea__chol_lower(kk, L, kk, 1.0); /* L L^T = I + S */
    if (st)
        return st;
    for (int j = 0; j < kk; j++) { /* Z1 = U^T L^-T, column by column */
        double *z = Z1 + j * M;
        memcpy(z, ut + j * M, M * sizeof(double));
        for (int l = 0; l < j; l++)
            axpy(m, -L[j + (size_t)l * kk], Z1 + l * M, z);
        scal(m, 1.0 / L[j + (size_t)j * kk], z);
    }
    for (int j = kk - 1; j >= 0; j--) { /* T = Z1 L^-1 = U^T M^-1 */
        double *t = T + j * M;
        memcpy(t, Z1 + j * M, M * sizeof(double));
        for (int l = j + 1; l < kk; l++)
            axpy(m, -L[l + (size_t)j * kk], T + l * M, t);
        scal(m, 1.0 / L[j + (size_t)j * kk], t);
    }
    for (int j = 0; j < kk; j++) { /* D = G - U^T M^-1 (in T), Z2 = D L */
        double *d = T + j * M;
        const double *g = G + j * M;
        for (int i = 0; i < m; i++)
            d[i] = g[i] - d[i];
    }
    for (int j = 0; j < kk; j++) {
        double *z = Z2 + j * M;
        memset(z, 0, M * sizeof(double));
        for (int l = j; l < kk; l++)
            axpy(m, L[l + (size_t)j * kk], T + l * M, z);
    }
    if (!finite_block(2 * mk, GB))
        return IGEA_ENONFINITE;
    memcpy(BG, Z2, mk * sizeof(double));
    for (size_t t = 0; t < mk; t++)
        BG[mk + t] = -Z1[t];
    for (int i = 0; i < m; i++) {
        double dnew = src[(size_t)i * m + i] * linv;
        for (int l = 0; l < kk; l++)
            dnew += Z2[i + l * M] * Z2[i + l * M] - Z1[i + l * M] * Z1[i + l * M];
        if (!(dnew > 0.0 && dnew < INFINITY))
            return dnew > 0.0 || isnan(dnew) ? IGEA_ENONFINITE : IGEA_ESINGULAR;
    }
    return 0;
}

/* The update on kk rows whose whitened ct (m x kk), yw, innovations e,
 * A (kk x kk) and gt = Gamma c^T / lambda are in the scratch. Commits the
 * state on success. Returns 0, IGEA_ENONFINITE or IGEA_ESINGULAR, with the
 * state untouched on failure. */
/* The gains (METHODS 2.8 eigen form): Sigma_e = I + A = W diag(1 + a)
 * W^T, K = gt Sigma_e^-1 into h->KB and, for p > 1 gains, K_p = gt
 * f_p(Sigma_e) into h->KPB. Returns 1 when a p > 1 gain is used. */
static int core_gains(igea_rls *h, int kk)
{
    const int m = h->m, p = h->p;
    double *gt = h->gt;
    memcpy(h->Jw, h->A, (size_t)kk * kk * sizeof(double));
    jacobi_eig(kk, h->Jw, h->a, h->W);
    for (int j = 0; j < kk; j++) {
        double aj = h->a[j] > 0.0 ? h->a[j] : 0.0;
        h->r[j] = 1.0 / (1.0 + aj);
    }
    eig_func(kk, h->W, h->r, h->Mk);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, kk, kk, 1.0, gt,
                m, h->Mk, kk, 0.0, h->KB, m);
    const int multi = h->variant != IGEA_RLS_STANDARD && p > 1;
    if (multi) {
        for (int j = 0; j < kk; j++)
            h->r[j] = poly_gain(h->a[j] > 0.0 ? h->a[j] : 0.0, p);
        eig_func(kk, h->W, h->r, h->Mp);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, kk, kk, 1.0,
                    gt, m, h->Mp, kk, 0.0, h->KPB, m);
    }
    return multi;
}

/* The new state xn = x + gain e (the iterated variant: p passes with K). */
static int core_state(igea_rls *h, int kk, int multi)
{
    const int m = h->m, p = h->p;
    const double *K = h->KB, *gain = multi ? h->KPB : h->KB;
    memcpy(h->xn, h->x, (size_t)m * sizeof(double));
    if (multi && h->variant == IGEA_RLS_ITERATED) {
        /* METHODS 2.3 literally: p passes with the one gain K. */
        memcpy(h->r, h->e, (size_t)kk * sizeof(double));
        for (int it = 0; it < p; it++) {
            if (it > 0)
                resid(m, kk, h->ct, h->yw, h->xn, h->r);
            cblas_dgemv(CblasColMajor, CblasNoTrans, m, kk, 1.0, K, m, h->r, 1,
                        1.0, h->xn, 1);
        }
    } else {
        cblas_dgemv(CblasColMajor, CblasNoTrans, m, kk, 1.0, gain, m, h->e, 1,
                    1.0, h->xn, 1);
    }
    return finite_block((size_t)m, h->xn) ? 0 : IGEA_ENONFINITE;
}

/* Gamma in symmetric form (METHODS 2.8): Gamma/lambda - K Sigma_e K^T =
 * Gamma/lambda - V V^T, V = gt W diag((1 + a)^-1/2) into h->BK, a rank-kk
 * downdate that is symmetric bit for bit; its new diagonal must stay
 * positive and finite. */
static int core_gamma_factor(igea_rls *h, int kk, double linv)
{
    const int m = h->m;
    for (int j = 0; j < kk; j++) {
        double aj = h->a[j] > 0.0 ? h->a[j] : 0.0;
        double sj = 1.0 / sqrt(1.0 + aj);
        for (int i = 0; i < kk; i++)
            h->Jw[i + (size_t)j * kk] = h->W[i + (size_t)j * kk] * sj;
    }
    double *V = h->BK;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, kk, kk, 1.0, h->gt,
                m, h->Jw, kk, 0.0, V, m);
    if (!finite_block((size_t)m * kk, V))
        return IGEA_ENONFINITE;
    for (int i = 0; i < m; i++) {
        double dnew = h->gam[(size_t)i * m + i] * linv;
        for (int l = 0; l < kk; l++)
            dnew -= V[i + (size_t)l * m] * V[i + (size_t)l * m];
        if (!(dnew > 0.0 && dnew < INFINITY))
            return dnew > 0.0 || isnan(dnew) ? IGEA_ENONFINITE : IGEA_ESINGULAR;
    }
    return 0;
}

/* Commit the prepared update (nothing here can fail). */
static void core_commit(igea_rls *h, int kk, double linv, int multi, int cov_upd)
{
    const int m = h->m;
    double *V = h->BK;
    if (cov_upd) {
        if (h->p_same)
            memcpy(h->cov, h->gam, (size_t)m * m * sizeof(double));
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, m, m, 2 * kk, 1.0,
                    h->KPB, m, h->BKP, m, linv, h->cov, m);
        h->p_same = 0;
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, m, m, kk, -1.0, V, m,
                V, m, linv, h->gam, m);
    if (multi && !h->track_cov)
        h->cov_valid = 0;
    if (++h->since_sym >= 64) { /* keep the triangles bit-identical */
        mirror(m, h->gam);
        if (!h->p_same)
            mirror(m, h->cov);
        h->since_sym = 0;
    }
    double *t = h->x;
    h->x = h->xn;
    h->xn = t;
    resid(m, kk, h->ct, h->yw, h->x, h->r);
    for (int j = 0; j < kk; j++)
        igea__ksum_add(&h->q, h->r[j] * h->r[j]);
    h->counts[IGEA_RLS_COUNT_ROWS] += kk;
    h->counts[IGEA_RLS_COUNT_UPDATES]++;
}

static int core_update(igea_rls *h, int kk)
{
    const int m = h->m;
    const size_t mk = (size_t)m * kk;
    const double linv = 1.0 / h->lambda;
    const int multi = core_gains(h, kk);
    int st = core_state(h, kk, multi);
    if (st == 0)
        st = core_gamma_factor(h, kk, linv);
    if (st != 0)
        return st;
    /* P: the gain actually used (Joseph form, factored), unless P == Gamma. */
    const int cov_upd = h->track_cov && (multi || !h->p_same);
    if (cov_upd) {
        if (!multi) /* P != Gamma but the gain is K: copy it as the P gain */
            memcpy(h->KPB, h->KB, mk * sizeof(double));
        const double *src = h->p_same ? h->gam : h->cov;
        const double *ut = h->gt;
        if (!h->p_same) {
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, kk, m,
                        linv, h->cov, m, h->ct, m, 0.0, h->ut, m);
            ut = h->ut;
        }
        st = cov_prepare(h, kk, linv, src, ut, h->KPB, h->KPB, h->BKP);
        if (st != 0)
            return st;
    }
    core_commit(h, kk, linv, multi, cov_upd);
    return 0;
}

/* Whitened innovations e = yw - ct^T x, yw = y / sigma, over all k rows. */
static void innovations(igea_rls *h, const double *y, const double *sig)
{
    for (int j = 0; j < h->k; j++)
        h->yw[j] = sig ? y[j] / sig[j] : y[j];
    resid(h->m, h->k, h->ct, h->yw, h->x, h->e);
}

/* One epoch with c(j, i) at c[j * rs + i * cs] (arguments checked). */
/* Detection (METHODS 2.7): the flags of the k rows into h->fl; returns
 * the number of flagged rows. */
static int detect(igea_rls *h, const double *y)
{
    const int k = h->k;
    int nflag = 0;
    for (int j = 0; j < k; j++) {
        int f = 0;
        if (!isfinite(y[j])) {
            f |= IGEA_RLS_FLAG_MISSING;
        } else {
            double sd = sqrt(1.0 + (h->A[j + (size_t)j * k] > 0 ? h->A[j + (size_t)j * k] : 0.0));
            if (fabs(h->e[j]) > h->kappa * sd)
                f |= IGEA_RLS_FLAG_INNOVATION;
            if (h->has_jump && h->yprev_ok[j] &&
                fabs(y[j] - h->yprev[j]) > h->jump_max[j])
                f |= IGEA_RLS_FLAG_JUMP;
        }
        h->fl[j] = f;
        if (f)
            nflag++;
    }
    return nflag;
}

/* Isolation: the unflagged rows compressed to the first *kk columns of ct,
 * gt (and yw, e, A). */
static void isolate_rows(igea_rls *h, int *kk_out)
{
    const int m = h->m, k = h->k;
    int kk = 0;
    for (int j = 0; j < k; j++) {
        h->keep[j] = h->fl[j] == 0;
        if (!h->keep[j])
            continue;
        if (kk != j) {
            memcpy(h->ct + (size_t)kk * m, h->ct + (size_t)j * m, (size_t)m * sizeof(double));
            memcpy(h->gt + (size_t)kk * m, h->gt + (size_t)j * m, (size_t)m * sizeof(double));
            h->yw[kk] = h->yw[j];
            h->e[kk] = h->e[j];
        }
        h->r[kk] = (double)j; /* original row of kept row kk */
        kk++;
    }
    for (int jj = 0; jj < kk; jj++)
        for (int ii = jj; ii < kk; ii++) {
            int i0 = (int)h->r[ii], j0 = (int)h->r[jj];
            h->Sm[ii + (size_t)jj * kk] = h->Sm[jj + (size_t)ii * kk] =
                h->A[i0 + (size_t)j0 * k];
        }
    memcpy(h->A, h->Sm, (size_t)kk * kk * sizeof(double));
    *kk_out = kk;
}

/* The anomaly policy on nflag flagged rows: the action, and *kk the rows
 * the update uses (0: none). */
static int apply_policy(igea_rls *h, const double *y, const double *track_sigma,
                        int nflag, int *kk)
{
    const int k = h->k;
    for (int j = 0; j < k; j++) {
        h->keep[j] = 1;
        h->yused[j] = y[j];
    }
    if (!nflag)
        return IGEA_RLS_UPDATED;
    if (h->policy == IGEA_RLS_ANOMALY_NONE)
        return IGEA_RLS_FLAGGED;
    int all_prev = 1;
    for (int j = 0; j < k; j++)
        all_prev &= h->yprev_ok[j];
    if (h->policy == IGEA_RLS_ANOMALY_SKIP ||
        (h->policy == IGEA_RLS_ANOMALY_REPLACE && !all_prev) ||
        (h->policy == IGEA_RLS_ANOMALY_ISOLATE && nflag == k)) {
        *kk = 0;
        return IGEA_RLS_SKIPPED;
    }
    if (h->policy == IGEA_RLS_ANOMALY_REPLACE) {
        memcpy(h->yused, h->yprev, (size_t)k * sizeof(double));
        innovations(h, h->yused, track_sigma);
        return IGEA_RLS_REPLACED;
    }
    isolate_rows(h, kk); /* isolate: compress to the unflagged rows */
    return IGEA_RLS_ISOLATED;
}

static int update_impl(igea_rls *h, const double *c, size_t rs, size_t cs,
                       const double *y, const double *track_sigma, int *flags)
{
    const int m = h->m, k = h->k;
    if (track_sigma) {
        int st = igea__sigma_vec(k, track_sigma);
        if (st)
            return st;
    }
    int nmissing = 0;
    for (int j = 0; j < k; j++)
        if (!isfinite(y[j]))
            nmissing++;
    if (nmissing && h->policy == IGEA_RLS_ANOMALY_NONE)
        return IGEA_ENONFINITE;

    /* Whiten: ct (m x k) = (c / sigma)^T. */
    const double linv = 1.0 / h->lambda;
    for (int j = 0; j < k; j++) {
        double s = track_sigma ? 1.0 / track_sigma[j] : 1.0;
        double *col = h->ct + (size_t)j * m;
        for (int i = 0; i < m; i++)
            col[i] = c[(size_t)j * rs + (size_t)i * cs] * s;
    }
    /* gt = Gamma c^T / lambda, A = c gt. */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, k, m, linv,
                h->gam, m, h->ct, m, 0.0, h->gt, m);
    small_sym(m, k, h->ct, h->gt, h->A);
    innovations(h, y, track_sigma);

    int nflag = detect(h, y);
    int kk = k;
    int action = apply_policy(h, y, track_sigma, nflag, &kk);
    if (kk > 0) {
        int st = core_update(h, kk);
        if (st != 0)
            return st;
    }
    /* Bookkeeping (the update, if any, is committed). */
    for (int j = 0; j < k; j++) {
        int used = kk > 0 && h->keep[j];
        if (used && action != IGEA_RLS_REPLACED) {
            h->yprev[j] = y[j];
            h->yprev_ok[j] = 1;
        }
        if (flags)
            flags[j] = h->fl[j] | (used ? 0 : IGEA_RLS_FLAG_UNUSED);
    }
    h->counts[IGEA_RLS_COUNT_EPOCHS]++;
    if (nflag)
        h->counts[IGEA_RLS_COUNT_ANOMALOUS]++;
    return action;
}

int igea_rls_update(igea_rls *h, const double *c, int ldc, const double *y,
                    const double *track_sigma, int *flags)
{
    if (!h)
        return -1;
    if (!c)
        return -2;
    if (ldc < h->k)
        return -3;
    if (!y)
        return -4;
    if (!igea__finite_mat(h->k, h->m, c, ldc))
        return IGEA_ENONFINITE;
    return update_impl(h, c, 1, (size_t)ldc, y, track_sigma, flags);
}

int igea_rls_run(igea_rls *h, int n, int layout, const double *S, int lds,
                 const double *dw, const double *track_sigma, int sigma_inc,
                 double *x_out, int ldx, int *flags, int *actions, int *n_done)
{
    if (!h)
        return -1;
    if (n < 0)
        return -2;
    const int k = h->k, m = h->m;
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR)
        return -3;
    if (!S && n > 0)
        return -4;
    if (layout == IGEA_COLMAJOR ? (double)lds < IGEA_MAX(1.0, (double)n * k)
                                       : lds < m)
        return -5;
    if (!dw && n > 0)
        return -6;
    if (sigma_inc != 0 && sigma_inc != 1)
        return -8;
    if (x_out && ldx < m)
        return -10;
    /* The arguments are valid: from here *n_done reports progress, also
     * when an epoch fails (the documented exception to untouched outputs). */
    if (n_done)
        *n_done = 0;
    for (int e = 0; e < n; e++) {
        size_t row = (size_t)e * (size_t)k;
        const double *sig = track_sigma ? track_sigma + (sigma_inc ? row : 0) : NULL;
        const double *c;
        size_t rs, cs;
        if (layout == IGEA_COLMAJOR) {
            c = S + row;
            rs = 1;
            cs = (size_t)lds;
            if (!igea__finite_mat(k, m, c, lds))
                return IGEA_ENONFINITE;
        } else {
            c = S + row * (size_t)lds;
            rs = (size_t)lds;
            cs = 1;
            if (!finite_strided(m, k, c, (size_t)lds))
                return IGEA_ENONFINITE;
        }
        int st = update_impl(h, c, rs, cs, dw + row, sig,
                             flags ? flags + row : NULL);
        if (st < 0)
            return st;
        if (x_out)
            memcpy(x_out + (size_t)e * (size_t)ldx, h->x, (size_t)h->m * sizeof(double));
        if (actions)
            actions[e] = st;
        if (n_done)
            *n_done = e + 1;
    }
    return 0;
}

/* ---- getters ------------------------------------------------------------ */

int igea_rls_get_x(const igea_rls *h, double *x)
{
    if (!h)
        return -1;
    if (!x)
        return -2;
    memcpy(x, h->x, (size_t)h->m * sizeof(double));
    return 0;
}

static int get_sym(const igea_rls *h, const double *src, double *out, int ld)
{
    if (!h)
        return -1;
    if (!out)
        return -2;
    if (ld < h->m)
        return -3;
    const int m = h->m;
    for (int j = 0; j < m; j++)
        for (int i = j; i < m; i++)
            IGEA_AT(out, ld, i, j) = IGEA_AT(out, ld, j, i) = src[i + (size_t)j * m];
    return 0;
}

int igea_rls_get_gamma(const igea_rls *h, double *gamma, int ldg)
{
    return get_sym(h, h ? h->gam : NULL, gamma, ldg);
}

int igea_rls_get_covariance(const igea_rls *h, double *cov, int ldc)
{
    if (!h)
        return -1;
    if (!h->cov_valid)
        return !cov ? -2 : ldc < h->m ? -3 : IGEA_EDOMAIN;
    return get_sym(h, h->p_same ? h->gam : h->cov, cov, ldc);
}

int igea_rls_get_sd(const igea_rls *h, double *sd)
{
    if (!h)
        return -1;
    if (!sd)
        return -2;
    if (!h->cov_valid)
        return IGEA_EDOMAIN;
    const double *P = h->p_same ? h->gam : h->cov;
    for (int i = 0; i < h->m; i++)
        if (!(P[i + (size_t)i * h->m] >= 0) || !isfinite(P[i + (size_t)i * h->m]))
            return IGEA_EDOMAIN; /* not reached for a positive definite state */
    for (int i = 0; i < h->m; i++)
        sd[i] = sqrt(P[i + (size_t)i * h->m]);
    return 0;
}

int igea_rls_get_q(const igea_rls *h, double *q)
{
    if (!h)
        return -1;
    if (!q)
        return -2;
    *q = igea__ksum_get(&h->q);
    return 0;
}

int igea_rls_get_counts(const igea_rls *h, int *counts)
{
    if (!h)
        return -1;
    if (!counts)
        return -2;
    memcpy(counts, h->counts, sizeof h->counts);
    return 0;
}

int igea_rls_get_size(const igea_rls *h, int *m, int *k)
{
    if (!h)
        return -1;
    if (m)
        *m = h->m;
    if (k)
        *k = h->k;
    return 0;
}

int igea_rls_compensate(const igea_rls *h, const double *c, int ldc,
                        const double *y, double *yhat)
{
    if (!h)
        return -1;
    if (!c)
        return -2;
    if (ldc < h->k)
        return -3;
    if (!y)
        return -4;
    if (!yhat)
        return -5;
    if (!igea__finite_mat(h->k, h->m, c, ldc) || !igea__finite_vec(h->k, y, 1))
        return IGEA_ENONFINITE;
    for (int j = 0; j < h->k; j++) {
        double s = 0.0;
        for (int i = 0; i < h->m; i++)
            s += IGEA_AT(c, ldc, j, i) * h->x[i];
        yhat[j] = y[j] - s;
    }
    return 0;
}
