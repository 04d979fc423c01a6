/* test_regress.c - least squares, ridge, PCE, Bayes, EBR and diagnostics.
 * References: METHODS 4.2 (20-position design) and 4.3 (EBR test vector);
 * NIST StRD Longley and Filip certified values (computed by NIST in
 * 500-digit arithmetic); closed forms derived in the comments. */
#include <float.h>

#include "testutil.h"

#include "igea/regress.h"
#include "internal.h"

#define PI_ 3.14159265358979323846

/* EBR with unit row weights and the posterior sds, the diagonal of the
 * covariance igea_regress_ebr returns (prior_scale is its spec_sigma). */
static int ebr_old(int m, int N, const double *A, int lda, const double *y,
                   const double *prior_scale, int rule, double lam_floor,
                   double *beta, double *lam, int *rank, double *shrink,
                   double *sd_post, double *sd_freq)
{
    double *cov = malloc((size_t)N * (size_t)N * sizeof(double)), s2;
    if (!cov)
        return IGEA_ENOMEM;
    int st = igea_regress_ebr(m, N, A, lda, y, NULL, prior_scale, rule, lam_floor, beta,
                              sd_post ? cov : NULL, N, lam, rank, &s2, NULL, shrink,
                              sd_freq);
    if (st == 0 && sd_post)
        for (int j = 0; j < N; j++)
            sd_post[j] = sqrt(cov[j + (size_t)j * N]);
    free(cov);
    return st;
}

static const double filip_y[82] = {0.8116, 0.9072, 0.9052, 0.9039, 0.8053, 0.8377, 0.8667, 0.8809, 0.7975, 0.8162, 0.8515, 0.8766, 0.8885, 0.8859, 0.8959, 0.8913, 0.8959, 0.8971, 0.9021, 0.909, 0.9139, 0.9199, 0.8692, 0.8872, 0.89, 0.891, 0.8977, 0.9035, 0.9078, 0.7675, 0.7705, 0.7713, 0.7736, 0.7775, 0.7841, 0.7971, 0.8329, 0.8641, 0.8804, 0.7668, 0.7633, 0.7678, 0.7697, 0.77, 0.7749, 0.7796, 0.7897, 0.8131, 0.8498, 0.8741, 0.8061, 0.846, 0.8751, 0.8856, 0.8919, 0.8934, 0.894, 0.8957, 0.9047, 0.9129, 0.9209, 0.9219, 0.7739, 0.7681, 0.7665, 0.7703, 0.7702, 0.7761, 0.7809, 0.7961, 0.8253, 0.8602, 0.8809, 0.8301, 0.8664, 0.8834, 0.8898, 0.8964, 0.8963, 0.9074, 0.9119, 0.9228};
static const double filip_x[82] = {-6.860120914, -4.324130045, -4.358625055, -4.358426747, -6.955852379, -6.661145254, -6.355462942, -6.118102026, -7.115148017, -6.815308569, -6.519993057, -6.204119983, -5.853871964, -6.109523091, -5.79832982, -5.482672118, -5.171791386, -4.851705903, -4.517126416, -4.143573228, -3.709075441, -3.499489089, -6.300769497, -5.953504836, -5.642065153, -5.031376979, -4.680685696, -4.329846955, -3.928486195, -8.56735134, -8.363211311, -8.107682739, -7.823908741, -7.522878745, -7.218819279, -6.920818754, -6.628932138, -6.323946875, -5.991399828, -8.781464495, -8.663140179, -8.473531488, -8.247337057, -7.971428747, -7.676129393, -7.352812702, -7.072065318, -6.774174009, -6.478861916, -6.159517513, -6.835647144, -6.53165267, -6.224098421, -5.910094889, -5.598599459, -5.290645224, -4.974284616, -4.64454848, -4.290560426, -3.885055584, -3.408378962, -3.13200249, -8.726767166, -8.66695597, -8.511026475, -8.165388579, -7.886056648, -7.588043762, -7.283412422, -6.995678626, -6.691862621, -6.392544977, -6.067374056, -6.684029655, -6.378719832, -6.065855188, -5.752272167, -5.132414673, -4.811352704, -4.098269308, -3.66174277, -3.2644011};

/* NIST StRD Filip: y = B0 + B1 x + ... + B10 x^10, certified values. */
static const double filip_b[11] = {
    -1467.48961422980, -2772.17959193342, -2316.37108160893,
    -1127.97394098372, -354.478233703349, -75.1242017393757,
    -10.8753180355343, -1.06221498588947, -0.670191154593408E-01,
    -0.246781078275479E-02, -0.402962525080404E-04};
static const double filip_sd[11] = {
    298.084530995537, 559.779865474950, 466.477572127796, 227.204274477751,
    71.6478660875927, 15.2897178747400, 2.23691159816033, 0.221624321934227,
    0.142363763154724E-01, 0.535617408889821E-03, 0.896632837373868E-05};

/* NIST StRD Longley: y, x1..x6 (16 rows), certified B0..B6 and sds. */
static const double longley[16][7] = {
    {60323, 83.0, 234289, 2356, 1590, 107608, 1947},
    {61122, 88.5, 259426, 2325, 1456, 108632, 1948},
    {60171, 88.2, 258054, 3682, 1616, 109773, 1949},
    {61187, 89.5, 284599, 3351, 1650, 110929, 1950},
    {63221, 96.2, 328975, 2099, 3099, 112075, 1951},
    {63639, 98.1, 346999, 1932, 3594, 113270, 1952},
    {64989, 99.0, 365385, 1870, 3547, 115094, 1953},
    {63761, 100.0, 363112, 3578, 3350, 116219, 1954},
    {66019, 101.2, 397469, 2904, 3048, 117388, 1955},
    {67857, 104.6, 419180, 2822, 2857, 118734, 1956},
    {68169, 108.4, 442769, 2936, 2798, 120445, 1957},
    {66513, 110.8, 444546, 4681, 2637, 121950, 1958},
    {68655, 112.6, 482704, 3813, 2552, 123366, 1959},
    {69564, 114.2, 502601, 3931, 2514, 125368, 1960},
    {69331, 115.7, 518173, 4806, 2572, 127852, 1961},
    {70551, 116.9, 554894, 4007, 2827, 130081, 1962}};
static const double longley_b[7] = {
    -3482258.63459582, 15.0618722713733, -0.358191792925910e-01,
    -2.02022980381683, -1.03322686717359, -0.511041056535807e-01,
    1829.15146461355};
static const double longley_sd[7] = {
    890420.383607373, 84.9149257747669, 0.334910077722432e-01,
    0.488399681651699, 0.214274163161675, 0.226073200069370,
    455.478499142212};
static const double longley_rsd = 304.854073561965;

/* Longley design with leading dimension lda (padding NaN). */
static void longley_design(int lda, double *A, double *y)
{
    fill_nan(A, (size_t)lda * 7);
    for (int i = 0; i < 16; i++) {
        A[i] = 1.0;
        for (int j = 1; j < 7; j++)
            A[i + (size_t)j * lda] = longley[i][j];
        y[i] = longley[i][0];
    }
}

/* METHODS 4.2: 20-position dual-accelerometer design (20 x 9), lda. */
static void dual_design(int lda, double *A)
{
    fill_nan(A, (size_t)lda * 9);
    for (int n = 0; n < 20; n++) {
        double th = 18.0 * n * PI_ / 180.0, s = sin(th), c = cos(th);
        double row[9] = {s, c, s * s, c * c, -s * c, s * s * s, c * c * c,
                         s * s * c, -s * c * c};
        for (int j = 0; j < 9; j++)
            A[n + (size_t)j * lda] = row[j];
    }
}

static const double ebr_beta_true[9] = {2e-4, -1.5e-4, 3e-4, -2e-4, 0.5e-4,
                                        0.2e-4, -0.1e-4, 0.1e-4, -0.2e-4};

/* METHODS 4.3 test vector: Y = A beta + a cos(7 theta + 0.3) + a/2 sin 5 theta. */
static void ebr_data(double a, int lda, double *A, double *y)
{
    dual_design(lda, A);
    for (int n = 0; n < 20; n++) {
        double th = 18.0 * n * PI_ / 180.0, v = 0.0;
        for (int j = 0; j < 9; j++)
            v += A[n + (size_t)j * lda] * ebr_beta_true[j];
        y[n] = v + a * cos(7.0 * th + 0.3) + 0.5 * a * sin(5.0 * th);
    }
}

/* ref printed with nd significant digits: got must round to it, i.e. lie
 * within half a unit of its last digit (plus a hair for binary ref). */
static void assert_digits_at(double got, double ref, int nd, int line)
{
    double e = floor(log10(fabs(ref)));
    double half = 0.5 * pow(10.0, e - nd + 1) * (1.0 + 1e-9);
    assert_close_at(got, ref, 0.0, half, __FILE__, line);
}
#define assert_digits(got, ref, nd) assert_digits_at((got), (ref), (nd), __LINE__)

/* ---- least squares ---- */

static void test_ls_longley(void **state)
{
    (void)state;
    int lda = 19;
    double A[19 * 7], y[16], x[7], cov[8 * 7], res[16], s2;
    int rank;
    longley_design(lda, A, y);
    assert_int_equal(igea_regress_ls(16, 7, A, lda, y, NULL, NULL, 0.0, x, cov, 8,
                                     &rank, &s2, res), 0);
    assert_int_equal(rank, 7);
    /* >= 10 significant digits against NIST's certified values. */
    for (int j = 0; j < 7; j++) {
        assert_close(x[j], longley_b[j], 1e-10);
        assert_close(sqrt(cov[j + 8 * j]), longley_sd[j], 1e-10);
    }
    assert_close(sqrt(s2), longley_rsd, 1e-10);
    double r0 = y[0];
    for (int j = 0; j < 7; j++)
        r0 -= A[(size_t)j * lda] * x[j];
    assert_close_abs(res[0], r0, 1e-9, 1e-6);
}

static void test_ls_filip(void **state)
{
    (void)state;
    /* Degree-10 polynomial, cond(A) ~ 1.8e15 (5e9 after column
     * equilibration): >= 7 significant digits required. */
    double A[82 * 11], x[11], cov[11 * 11], s2;
    int rank;
    for (int i = 0; i < 82; i++) {
        double p = 1.0;
        for (int j = 0; j < 11; j++) {
            A[i + 82 * j] = p;
            p *= filip_x[i];
        }
    }
    assert_int_equal(igea_regress_ls(82, 11, A, 82, filip_y, NULL, NULL, 0.0, x,
                                     cov, 11, &rank, &s2, NULL), 0);
    assert_int_equal(rank, 11);
    for (int j = 0; j < 11; j++) {
        assert_close(x[j], filip_b[j], 1e-7);
        assert_close(sqrt(cov[j + 11 * j]), filip_sd[j], 1e-7);
    }
}

/* ---- NIST StRD linear regression: all 11 problems ---- */

/* The files in tests/data/strd/ are NIST's Statistical Reference Datasets
 * for linear least squares (https://www.itl.nist.gov/div898/strd/lls/,
 * a US Government work, public domain): the certified B_j and their
 * standard deviations (NIST: 500-digit arithmetic) in the lines
 * "B<j> estimate sd", the data after the last line starting "Data:". */
typedef struct {
    int n, p;
    double b[11], sd[11], y[100], x[100][6];
} strd;

static int strd_read(const char *name, int npred, strd *d)
{
    char path[256], line[512];
    snprintf(path, sizeof path, "tests/data/strd/%s.dat", name);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    long data_at = -1;
    d->n = d->p = 0;
    while (fgets(line, sizeof line, f)) {
        int j;
        double b, s;
        if (sscanf(line, " B%d %lf %lf", &j, &b, &s) == 3 && d->p < 11) {
            d->b[d->p] = b;
            d->sd[d->p++] = s;
        }
        if (strncmp(line, "Data:", 5) == 0)
            data_at = ftell(f);
    }
    fseek(f, data_at, SEEK_SET);
    while (d->n < 100 && fscanf(f, "%lf", &d->y[d->n]) == 1) {
        for (int k = 0; k < npred; k++)
            if (fscanf(f, "%lf", &d->x[d->n][k]) != 1)
                return fclose(f), -1;
        d->n++;
    }
    fclose(f);
    return data_at < 0 ? -1 : 0;
}

/* Log relative error, capped at 15 (absolute when the certified value is 0). */
static double lre(double got, double cert)
{
    double e = cert != 0.0 ? fabs(got - cert) / fabs(cert) : fabs(got);
    return e > 0 ? IGEA_MIN(15.0, -log10(e)) : 15.0;
}

/* kind 0: polynomial in x of degree p - 1; 1: y = B1 x (no intercept);
 * 2: intercept and npred columns. Minimum LRE over coefficients and sds. */
static void strd_fit(const char *name, int kind, int npred, int flags, double *lre_b,
                     double *lre_sd)
{
    strd d;
    assert_int_equal(strd_read(name, npred, &d), 0);
    int n = d.n, p = d.p;
    double *A = malloc(sizeof(double) * (size_t)n * (size_t)p), x[11], sd[11], s2, info[16];
    assert_non_null(A);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < p; j++)
            A[i + (size_t)j * n] = kind == 1 ? d.x[i][0] : kind == 2 ? (j ? d.x[i][j - 1] : 1.0)
                                                                     : pow(d.x[i][0], j);
    assert_int_equal(igea_regress_ls_ex(n, p, A, n, d.y, NULL, NULL, 0.0, flags, x, NULL, 0, sd,
                                        &s2, NULL, info), 0);
    assert_true(info[IGEA_REGRESS_INFO_RANK] == p);
    *lre_b = *lre_sd = 15.0;
    for (int j = 0; j < p; j++) {
        *lre_b = IGEA_MIN(*lre_b, lre(x[j], d.b[j]));
        *lre_sd = IGEA_MIN(*lre_sd, lre(sd[j], d.sd[j]));
    }
    free(A);
}

static void test_ls_strd(void **state)
{
    (void)state;
    static const struct { const char *name; int kind, npred; double min_b, min_sd; } P[] = {
        {"Norris", 0, 1, 9, 9},   {"Pontius", 0, 1, 9, 9},  {"NoInt1", 1, 1, 9, 9},
        {"NoInt2", 1, 1, 9, 9},   {"Filip", 0, 1, 7, 7},    {"Longley", 2, 6, 9, 9},
        {"Wampler1", 0, 1, 9, 9}, {"Wampler2", 0, 1, 9, 9}, {"Wampler3", 0, 1, 9, 9},
        {"Wampler4", 0, 1, 9, 9}, {"Wampler5", 0, 1, 9, 9}};
    for (size_t k = 0; k < sizeof P / sizeof P[0]; k++) {
        double lb, ls, lb0, ls0;
        strd_fit(P[k].name, P[k].kind, P[k].npred, 0, &lb, &ls);
        strd_fit(P[k].name, P[k].kind, P[k].npred, IGEA_REGRESS_NO_REFINE, &lb0, &ls0);
        print_message("%-9s LRE coef %5.2f sd %5.2f (unrefined %5.2f %5.2f)\n", P[k].name, lb, ls,
                      lb0, ls0);
        assert_true(lb >= P[k].min_b);
        assert_true(ls >= P[k].min_sd);
    }
}

/* Row weights leave Wampler5's solution unchanged when they are equal;
 * with sigma = 3 (1/3 not a double) the refinement keeps the weights
 * exact (fmal remainders) and still returns x = 1 to 14 digits. */
static void test_ls_strd_weighted(void **state)
{
    (void)state;
    strd d;
    assert_int_equal(strd_read("Wampler5", 1, &d), 0);
    double A[21 * 6], x[6], sd[6], sig[21], s2, info[IGEA_REGRESS_INFO_LEN];
    for (int i = 0; i < 21; i++) {
        sig[i] = 3.0;
        for (int j = 0; j < 6; j++)
            A[i + 21 * j] = pow(d.x[i][0], j);
    }
    assert_int_equal(igea_regress_ls_ex(21, 6, A, 21, d.y, sig, NULL, 0.0, 0, x, NULL, 0, sd, &s2,
                                        NULL, info), 0);
    for (int j = 0; j < 6; j++) {
        assert_true(lre(x[j], 1.0) >= 14.0);
        assert_close(sd[j], d.sd[j], 1e-12); /* s^2 = RSS_w / (m - r) absorbs the scale */
    }
}

/* Filip: the exact least-squares solution of the double-precision design
 * (pow(x, j) of the doubles read from Filip.dat) and y, by mpmath 1.3.0
 * at 80 digits (normal equations in exact binary inputs:
 *   M = mpmath.matrix([[mpmath.mpf(math.pow(v, j)) for j in range(11)] for v in x])
 *   b = mpmath.lu_solve(M.T * M, M.T * Y)).
 * It agrees with NIST's certified values (exact decimal data) to LRE 7.61
 * only: the rounding of the data to doubles moves the solution that far
 * (scaled condition number 5.2e9). igea must reproduce it to 13 digits. */
static const double filip_exact[11] = {
    -1467.4896406575195, -2772.1796428402328, -2316.3711251051091, -1127.973962693167,
    -354.47824071352111, -75.124203269885366, -10.875318264388821, -1.0622150090377793,
    -0.067019116975598725, -0.0024678108408518231, -4.0296253497222846e-5};

static void test_ls_filip_exact(void **state)
{
    (void)state;
    strd d;
    assert_int_equal(strd_read("Filip", 1, &d), 0);
    double A[82 * 11], x[11], s2, info[16];
    for (int i = 0; i < 82; i++)
        for (int j = 0; j < 11; j++)
            A[i + 82 * j] = pow(d.x[i][0], j);
    assert_int_equal(igea_regress_ls_ex(82, 11, A, 82, d.y, NULL, NULL, 0.0, 0, x, NULL, 0, NULL,
                                        &s2, NULL, info), 0);
    for (int j = 0; j < 11; j++)
        assert_close(x[j], filip_exact[j], 1e-13);
    assert_true(info[IGEA_REGRESS_INFO_REFINE_STEPS] >= 1);
    assert_true(info[IGEA_REGRESS_INFO_SCALED] == 1.0);
}

/* igea_regress_sd: sqrt of the diagonal (ldc > N), refusals. */
static void test_regress_sd(void **state)
{
    (void)state;
    double cov[3 * 2] = {4.0, 1.0, NAN, 1.0, 2.25, NAN}, sd[2] = {-1, -1};
    assert_int_equal(igea_regress_sd(2, cov, 3, sd), 0);
    assert_true(sd[0] == 2.0 && sd[1] == 1.5);
    cov[4] = -1e-30;
    sd[0] = sd[1] = -1;
    assert_int_equal(igea_regress_sd(2, cov, 3, sd), IGEA_EDOMAIN);
    cov[4] = INFINITY;
    assert_int_equal(igea_regress_sd(2, cov, 3, sd), IGEA_ENONFINITE);
    assert_true(sd[0] == -1 && sd[1] == -1);
    assert_int_equal(igea_regress_sd(0, cov, 3, sd), -1);
    assert_int_equal(igea_regress_sd(2, NULL, 3, sd), -2);
    assert_int_equal(igea_regress_sd(2, cov, 1, sd), -3);
    assert_int_equal(igea_regress_sd(2, cov, 3, NULL), -4);
}

/* Ridge and PCE on a design whose third column is 1e-15 of the others:
 * unscaled, its singular value falls below the rank cut and the component
 * is dropped (x_3 = 0); the _ex functions scale the columns, keep rank 3
 * and recover the exact-fit coefficients (y = A x_true, k = 0 and all
 * components: least squares, x = x_true). */
static void test_ridge_pce_autoscale(void **state)
{
    (void)state;
    enum { M = 12, NC = 3 };
    double A[M * NC], y[M], x[NC], s2, ku, info[IGEA_REGRESS_INFO_LEN];
    const double xt[NC] = {1.5, -0.75, 2e15};
    for (int i = 0; i < M; i++) {
        double t = (double)i / (M - 1);
        A[i] = 1.0;
        A[i + M] = t;
        A[i + 2 * M] = 1e-15 * t * t;
        y[i] = xt[0] + xt[1] * t + 2.0 * t * t; /* = A xt up to rounding */
    }
    assert_int_equal(igea_regress_ridge(M, NC, A, M, y, NULL, NULL, IGEA_REGRESS_RIDGE_FIXED,
                                        0.0, x, NULL, 0, &ku, &s2, NULL), 0);
    assert_true(fabs(x[2]) < 1.0); /* x_3 = 2e15 lost: what the _ex functions avoid */
    assert_int_equal(igea_regress_ridge_ex(M, NC, A, M, y, NULL, NULL, IGEA_REGRESS_RIDGE_FIXED,
                                           0.0, x, NULL, 0, &ku, &s2, NULL, info), 0);
    assert_true(info[IGEA_REGRESS_INFO_RANK] == 3.0 && info[IGEA_REGRESS_INFO_SCALED] == 1.0);
    for (int j = 0; j < NC; j++)
        assert_close(x[j], xt[j], 1e-12);
    int nused;
    assert_int_equal(igea_regress_pce_ex(M, NC, A, M, y, NULL, NULL, 0, 1e-6, x, NULL, 0,
                                         &nused, &s2, NULL, info), 0);
    assert_int_equal(nused, 3);
    assert_true(info[IGEA_REGRESS_INFO_SCALED] == 1.0);
    for (int j = 0; j < NC; j++)
        assert_close(x[j], xt[j], 1e-12);
    /* A well-scaled design is left as it is: the same numbers as ridge. */
    double x2[NC], ku2;
    for (int i = 0; i < M; i++)
        A[i + 2 * M] = ((double)i / (M - 1)) * ((double)i / (M - 1));
    assert_int_equal(igea_regress_ridge(M, NC, A, M, y, NULL, NULL, IGEA_REGRESS_RIDGE_HKB, 0.0,
                                        x2, NULL, 0, &ku2, &s2, NULL), 0);
    assert_int_equal(igea_regress_ridge_ex(M, NC, A, M, y, NULL, NULL, IGEA_REGRESS_RIDGE_HKB,
                                           0.0, x, NULL, 0, &ku, &s2, NULL, info), 0);
    assert_true(info[IGEA_REGRESS_INFO_SCALED] == 0.0 && ku == ku2);
    for (int j = 0; j < NC; j++)
        assert_true(x[j] == x2[j]);
    assert_true(info[IGEA_REGRESS_INFO_RCOND] == M * DBL_EPSILON);
    assert_int_equal(igea_regress_ridge_ex(M, NC, A, M, y, NULL, NULL, 0, 0.0, x, NULL, 0, &ku,
                                           &s2, NULL, NULL), -16);
}

/* R^2 and the ANOVA F statistic against NIST's certified values (the
 * "Certified Analysis of Variance Table" of each StRD file; R^2 is
 * uncentred for the no-intercept NoInt1, as statsmodels has it). */
static void test_ls_diag_strd(void **state)
{
    (void)state;
    static const struct { const char *name; int kind, npred; double r2, F, rsd; } P[] = {
        {"Norris", 0, 1, 0.999993745883712, 5436385.54079785, 0.884796396144373},
        {"Pontius", 0, 1, 0.999999900178537, 185330865.995752, 0.205177424076185E-03},
        {"NoInt1", 1, 1, 0.999365492298663, 15750.2500000000, 3.56753034006338},
        {"Longley", 2, 6, 0.995479004577296, 330.285339234588, 304.854073561965}};
    for (size_t k = 0; k < sizeof P / sizeof P[0]; k++) {
        strd d;
        assert_int_equal(strd_read(P[k].name, P[k].npred, &d), 0);
        int n = d.n, p = d.p;
        double *A = malloc(sizeof(double) * (size_t)n * (size_t)p), x[11], sd[11];
        double dg[IGEA_REGRESS_DIAG_LEN], lev[100];
        assert_non_null(A);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < p; j++)
                A[i + (size_t)j * n] = P[k].kind == 1 ? d.x[i][0]
                                       : P[k].kind == 2 ? (j ? d.x[i][j - 1] : 1.0)
                                                        : pow(d.x[i][0], j);
        assert_int_equal(igea_regress_ls_diag(n, p, A, n, d.y, NULL, 0.0, 0.05, x, sd, NULL,
                                              NULL, NULL, NULL, lev, NULL, dg), 0);
        assert_close(dg[IGEA_REGRESS_DIAG_R2], P[k].r2, 1e-13);
        assert_close(dg[IGEA_REGRESS_DIAG_FVALUE], P[k].F, 1e-10);
        assert_close(sqrt(dg[IGEA_REGRESS_DIAG_SSR] / dg[IGEA_REGRESS_DIAG_DF_RESID]), P[k].rsd,
                     1e-11);
        assert_true(dg[IGEA_REGRESS_DIAG_CONSTANT] == (P[k].kind == 1 ? 0.0 : 1.0));
        double tr = 0.0; /* trace of the hat matrix = rank */
        for (int i = 0; i < n; i++)
            tr += lev[i];
        assert_close(tr, p, 1e-12);
        for (int j = 0; j < p; j++)
            assert_close(x[j], d.b[j], 1e-9);
        free(A);
    }
    /* an exact fit has no residual to test against */
    strd d;
    assert_int_equal(strd_read("Wampler1", 1, &d), 0);
    double A[21 * 6], x[6], sd[6], dg[IGEA_REGRESS_DIAG_LEN];
    for (int i = 0; i < 21; i++)
        for (int j = 0; j < 6; j++)
            A[i + 21 * j] = pow(d.x[i][0], j);
    assert_int_equal(igea_regress_ls_diag(21, 6, A, 21, d.y, NULL, 0.0, 0.05, x, sd, NULL, NULL,
                                          NULL, NULL, NULL, NULL, dg), IGEA_EDOMAIN);
    assert_int_equal(igea_regress_ls_diag(21, 6, A, 21, d.y, NULL, 0.0, 1.0, x, sd, NULL, NULL,
                                          NULL, NULL, NULL, NULL, dg), -8);
}

/* igea_regress_rank_info on a diagonal design (closed form: s = 3, 2,
 * 1e-20 after the row weights 1/sigma = 1): r = 2, cut 4 eps * 3, s1/s2. */
static void test_rank_info(void **state)
{
    (void)state;
    double A[4 * 3] = {3, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1e-20, 0}, info[IGEA_REGRESS_INFO_LEN];
    assert_int_equal(igea_regress_rank_info(4, 3, A, 4, NULL, NULL, 0.0, info), 0);
    assert_true(info[IGEA_REGRESS_INFO_RANK] == 2.0);
    assert_close(info[IGEA_REGRESS_INFO_TOL], 4 * DBL_EPSILON * 3.0, 1e-15);
    assert_close(info[IGEA_REGRESS_INFO_COND], 1.5, 1e-15);
    const double spec[3] = {1, 1, 1e10}; /* 1e-10: now above the cut */
    assert_int_equal(igea_regress_rank_info(4, 3, A, 4, NULL, spec, 0.0, info), 0);
    assert_true(info[IGEA_REGRESS_INFO_RANK] == 3.0);
    assert_int_equal(igea_regress_rank_info(4, 3, A, 4, NULL, NULL, 1.0, info), -7);
    assert_int_equal(igea_regress_rank_info(4, 3, A, 4, NULL, NULL, 0.0, NULL), -8);
}

/* ---- EBR ---- */

static void test_ebr_vector(void **state)
{
    (void)state;
    const double a[3] = {1e-6, 3e-5, 3e-4};
    const double lstar[3] = {4.3191821286e+04, 4.7812680709e+01,
                             3.1903350644e-01};
    const double shrink_ref[7] = {0.83916, 0.83916, 0.76136, 0.61467,
                                  0.44370, 0.26782, 0.26782};
    const double beta_ref[9] = {1.156185e-4, -8.07093e-5, 1.917349e-4,
                                -1.155993e-4, 2.21849e-5, 7.84732e-5,
                                -5.76305e-5, -2.30789e-5, -3.71453e-5};
    const int beta_nd[9] = {7, 6, 7, 7, 6, 6, 6, 6, 6};
    int lda = 23;
    double A[23 * 9], y[20], beta[9], lam, shrink[9], sdp[9], sdf[9];
    int rank;
    for (int t = 0; t < 3; t++) {
        ebr_data(a[t], lda, A, y);
        assert_int_equal(ebr_old(20, 9, A, lda, y, NULL, IGEA_REGRESS_EBR_SC,
                                          0.0, beta, &lam, &rank, shrink, sdp,
                                          sdf), 0);
        assert_int_equal(rank, 7);
        /* a = 1e-6: METHODS prints 4.3191821286e+04; the root with the
         * exact S = 12.5 a^2 (scipy brentq, rtol 1e-15) is
         * 4.319182128821e+04, so the printed 11th digit carries the
         * cancellation of S = |Y|^2 - sum z^2 (S is 1e-5 of |Y|^2 there):
         * 10 digits for that row, all 11 for the others. */
        assert_digits(lam, lstar[t], t == 0 ? 10 : 11);
        if (t == 0)
            assert_close(lam, 4.319182128821e+04, 1e-12);
    }
    for (int i = 0; i < 7; i++)
        assert_digits(shrink[i], shrink_ref[i], 5);
    for (int i = 7; i < 9; i++)
        assert_true(shrink[i] == 0.0);
    for (int j = 0; j < 9; j++)
        assert_digits(beta[j], beta_ref[j], beta_nd[j]);
}


/* ---- independent dense routines (Gauss-Jordan, partial pivoting) ---- */

/* inv = a^-1 for the n x n column-major a (n <= 12). Returns 0 if singular. */
static int gj_inverse(int n, const double *a, double *inv)
{
    double w[12 * 24];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 2 * n; j++)
            w[i * 24 + j] = j < n ? a[i + n * j] : (j - n == i);
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int i = c + 1; i < n; i++)
            if (fabs(w[i * 24 + c]) > fabs(w[p * 24 + c]))
                p = i;
        if (w[p * 24 + c] == 0.0)
            return 0;
        for (int j = 0; j < 2 * n; j++) {
            double t = w[c * 24 + j];
            w[c * 24 + j] = w[p * 24 + j];
            w[p * 24 + j] = t;
        }
        double d = w[c * 24 + c];
        for (int j = 0; j < 2 * n; j++)
            w[c * 24 + j] /= d;
        for (int i = 0; i < n; i++)
            if (i != c) {
                double f = w[i * 24 + c];
                for (int j = 0; j < 2 * n; j++)
                    w[i * 24 + j] -= f * w[c * 24 + j];
            }
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            inv[i + n * j] = w[i * 24 + n + j];
    return 1;
}

/* B = A^T A (+ k I) and b = A^T y for an m x N matrix (lda). */
static void normal_eq(int m, int N, const double *A, int lda, const double *y,
                      double k, double *B, double *b)
{
    for (int a = 0; a < N; a++) {
        for (int c = 0; c < N; c++) {
            double s = 0.0;
            for (int i = 0; i < m; i++)
                s += A[i + (size_t)a * lda] * A[i + (size_t)c * lda];
            B[a + N * c] = s + (a == c ? k : 0.0);
        }
        double s = 0.0;
        for (int i = 0; i < m; i++)
            s += A[i + (size_t)a * lda] * y[i];
        b[a] = s;
    }
}

static void matvec(int N, const double *M, const double *v, double *out)
{
    for (int a = 0; a < N; a++) {
        double s = 0.0;
        for (int c = 0; c < N; c++)
            s += M[a + N * c] * v[c];
        out[a] = s;
    }
}

/* ---- more least squares ---- */

static void test_ls_weighted_line(void **state)
{
    (void)state;
    /* Weighted straight line: closed forms with w_i = 1/sigma_i^2,
     * D = Sw Sxx - Sx^2, b = (Sw Sxy - Sx Sy)/D, a = (Sxx Sy - Sx Sxy)/D,
     * var(a) = s2 Sxx/D, var(b) = s2 Sw/D, cov = -s2 Sx/D. */
    const double xv[6] = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0};
    const double yv[6] = {1.1, 2.9, 5.2, 7.1, 8.8, 11.3};
    const double sg[6] = {0.1, 0.2, 0.1, 0.3, 0.2, 0.4};
    double A[8 * 2];
    fill_nan(A, 16);
    double Sw = 0, Sx = 0, Sy = 0, Sxx = 0, Sxy = 0;
    for (int i = 0; i < 6; i++) {
        A[i] = 1.0;
        A[i + 8] = xv[i];
        double w = 1.0 / (sg[i] * sg[i]);
        Sw += w;
        Sx += w * xv[i];
        Sy += w * yv[i];
        Sxx += w * xv[i] * xv[i];
        Sxy += w * xv[i] * yv[i];
    }
    double D = Sw * Sxx - Sx * Sx, b = (Sw * Sxy - Sx * Sy) / D,
           a = (Sxx * Sy - Sx * Sxy) / D, chi2 = 0.0;
    for (int i = 0; i < 6; i++) {
        double e = (yv[i] - a - b * xv[i]) / sg[i];
        chi2 += e * e;
    }
    double s2ref = chi2 / 4.0;
    double x[2], cov[3 * 2], s2, res[6];
    int rank;
    assert_int_equal(igea_regress_ls(6, 2, A, 8, yv, sg, NULL, 0.0, x, cov, 3, &rank,
                                     &s2, res), 0);
    assert_int_equal(rank, 2);
    assert_close(x[0], a, 1e-12);
    assert_close(x[1], b, 1e-12);
    assert_close(s2, s2ref, 1e-11);
    assert_close(cov[0], s2ref * Sxx / D, 1e-11);
    assert_close(cov[4], s2ref * Sw / D, 1e-11);
    assert_close(cov[1], -s2ref * Sx / D, 1e-11);
    assert_close(cov[3], -s2ref * Sx / D, 1e-11);
    assert_close(res[3], yv[3] - a - 3.0 * b, 1e-10);
}

static void test_ls_rank_deficient(void **state)
{
    (void)state;
    /* METHODS 4.2: rank 7, null space n1 (0, 5, 8) = (-1, 1, -1) and
     * n2 (1, 6, 7) = (-1, 1, 1); the minimum-norm solution is orthogonal
     * to both, and the residual is the added harmonics: S = 12.5 a^2. */
    int lda = 21;
    double A[21 * 9], y[20], x[9], cov[9 * 9], s2, res[20];
    int rank;
    ebr_data(3e-5, lda, A, y);
    assert_int_equal(igea_regress_ls(20, 9, A, lda, y, NULL, NULL, 0.0, x, cov, 9,
                                     &rank, &s2, res), 0);
    assert_int_equal(rank, 7);
    assert_close_abs(-x[0] + x[5] - x[8], 0.0, 0.0, 1e-18);
    assert_close_abs(-x[1] + x[6] + x[7], 0.0, 0.0, 1e-18);
    assert_close(s2, 12.5 * 3e-5 * 3e-5 / 13.0, 1e-9);
    /* estimable combinations are exact: k_A1, k_B1, eta, K_A0 + K_A2 */
    assert_close(x[2], ebr_beta_true[2], 1e-9);
    assert_close(x[3], ebr_beta_true[3], 1e-9);
    assert_close(x[4], ebr_beta_true[4], 1e-9);
    assert_close(x[0] + x[5], ebr_beta_true[0] + ebr_beta_true[5], 1e-9);
    /* cov n1 = 0 */
    for (int a = 0; a < 9; a++)
        assert_close_abs(-cov[a] + cov[a + 45] - cov[a + 72], 0.0, 0.0,
                         1e-12 * cov[2 + 18]);
    /* Two identical columns: the minimum norm splits the coefficient. */
    double B[2 * 5], yb[5] = {2, 4, 6, 8, 10.5}, xb[2], sb;
    for (int i = 0; i < 5; i++)
        B[i] = B[i + 5] = i + 1.0;
    assert_int_equal(igea_regress_ls(5, 2, B, 5, yb, NULL, NULL, 0.0, xb, NULL, 1,
                                     &rank, &sb, NULL), 0);
    assert_int_equal(rank, 1);
    double slope = (2 + 8 + 18 + 32 + 52.5) / 55.0;
    assert_close(xb[0], slope / 2, 1e-13);
    assert_close(xb[1], slope / 2, 1e-13);
    /* Wide problem (m < N): minimum norm x = A^T (A A^T)^-1 y. */
    double W[2 * 3] = {1, 0, 1, 1, 0, 1}, yw[2] = {1, 2}, xw[3], sw;
    assert_int_equal(igea_regress_ls(2, 3, W, 2, yw, NULL, NULL, 0.0, xw, NULL, 1,
                                     &rank, &sw, NULL), 0);
    assert_int_equal(rank, 2);
    /* A A^T = [[2,1],[1,2]], inverse [[2,-1],[-1,2]]/3; t = (0, 1) */
    assert_close_abs(xw[0], 0.0, 0, 1e-15);
    assert_close(xw[1], 1.0, 1e-14);
    assert_close(xw[2], 1.0, 1e-14);
    assert_true(sw == 0.0);
}

static void test_ls_errors(void **state)
{
    (void)state;
    double A[6] = {1, 2, 3, 1, 0, 1}, y[3] = {1, 2, 2}, sg[3] = {1, 1, 1};
    double x[2], cov[4], s2 = SENTINEL, res[3];
    int rank = -7;
    fill_sentinel(x, 2);
    fill_sentinel(cov, 4);
    fill_sentinel(res, 3);
#define LS(...) igea_regress_ls(__VA_ARGS__)
    assert_int_equal(LS(0, 2, A, 3, y, NULL, NULL, 0, x, cov, 2, &rank, &s2, res), -1);
    assert_int_equal(LS(3, 0, A, 3, y, NULL, NULL, 0, x, cov, 2, &rank, &s2, res), -2);
    assert_int_equal(LS(3, 2, NULL, 3, y, NULL, NULL, 0, x, cov, 2, &rank, &s2, res), -3);
    assert_int_equal(LS(3, 2, A, 2, y, NULL, NULL, 0, x, cov, 2, &rank, &s2, res), -4);
    assert_int_equal(LS(3, 2, A, 3, NULL, NULL, NULL, 0, x, cov, 2, &rank, &s2, res), -5);
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 1.0, x, cov, 2, &rank, &s2, res), -8);
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, NAN, x, cov, 2, &rank, &s2, res), -8);
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 0, NULL, cov, 2, &rank, &s2, res), -9);
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 0, x, cov, 1, &rank, &s2, res), -11);
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 0, x, cov, 2, NULL, &s2, res), -12);
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 0, x, cov, 2, &rank, NULL, res), -13);
    sg[1] = 0.0;
    assert_int_equal(LS(3, 2, A, 3, y, sg, NULL, 0, x, cov, 2, &rank, &s2, res),
                     IGEA_ENONPOSITIVE);
    sg[1] = NAN;
    assert_int_equal(LS(3, 2, A, 3, y, sg, NULL, 0, x, cov, 2, &rank, &s2, res),
                     IGEA_ENONFINITE);
    y[2] = INFINITY;
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 0, x, cov, 2, &rank, &s2, res),
                     IGEA_ENONFINITE);
    y[2] = 2;
    A[4] = NAN;
    assert_int_equal(LS(3, 2, A, 3, y, NULL, NULL, 0, x, cov, 2, &rank, &s2, res),
                     IGEA_ENONFINITE);
#undef LS
    assert_true(all_sentinel(x, 2) && all_sentinel(cov, 4) &&
                all_sentinel(res, 3) && s2 == SENTINEL && rank == -7);
}

/* ---- EBR: sds and the other rules ---- */

static void test_ebr_closed_forms(void **state)
{
    (void)state;
    /* With D_s = I: beta = M A^T y, M = (A^T A + I/lambda)^-1 (full rank
     * even though A is singular), posterior cov = s2 M, frequentist cov =
     * s2 M A^T A M, s2 = S / (m - r), S = |y - A x_LS|^2. */
    int lda = 20;
    double A[20 * 9], y[20], beta[9], lam, sh[9], sdp[9], sdf[9];
    int rank;
    ebr_data(1e-4, lda, A, y);
    assert_int_equal(ebr_old(20, 9, A, lda, y, NULL, IGEA_REGRESS_EBR_SC, 0.0,
                                      beta, &lam, &rank, sh, sdp, sdf), 0);
    double B[81], b[9], M[81], ref[9], xl[9], s2;
    int rl;
    assert_int_equal(igea_regress_ls(20, 9, A, lda, y, NULL, NULL, 0, xl, NULL, 1,
                                     &rl, &s2, NULL), 0);
    normal_eq(20, 9, A, lda, y, 1.0 / lam, B, b);
    assert_true(gj_inverse(9, B, M));
    matvec(9, M, b, ref);
    for (int j = 0; j < 9; j++)
        assert_close(beta[j], ref[j], 1e-8);
    double AtA[81], MB[81];
    normal_eq(20, 9, A, lda, y, 0.0, AtA, b);
    for (int j = 0; j < 9; j++) {
        assert_close(sdp[j], sqrt(s2 * M[j * 10]), 1e-8);
        /* (M AtA M)_jj */
        for (int c = 0; c < 9; c++)
            matvec(9, M, AtA + 9 * c, MB + 9 * c);
        double v = 0.0;
        for (int c = 0; c < 9; c++)
            v += MB[j + 9 * c] * M[c + 9 * j];
        assert_close(sdf[j], sqrt(s2 * v), 1e-7);
    }
    /* The SC equation holds: y^T A beta = |y|^2 - S - (r-2) S/(m-r+2). */
    double S = s2 * 13.0, yy = 0.0, yab = 0.0;
    for (int i = 0; i < 20; i++) {
        double ab = 0.0;
        for (int j = 0; j < 9; j++)
            ab += A[i + 20 * j] * beta[j];
        yy += y[i] * y[i];
        yab += y[i] * ab;
    }
    assert_close(yab, yy - S - 5.0 * S / 15.0, 1e-9);
    /* MM: y^T A beta = |y|^2 - S - r S/(m-r). */
    assert_int_equal(ebr_old(20, 9, A, lda, y, NULL, IGEA_REGRESS_EBR_MM, 0.0,
                                      beta, &lam, &rank, NULL, NULL, NULL), 0);
    yab = 0.0;
    for (int i = 0; i < 20; i++)
        for (int j = 0; j < 9; j++)
            yab += y[i] * A[i + 20 * j] * beta[j];
    assert_close(yab, yy - S - 7.0 * S / 13.0, 1e-9);
}

static void test_ebr_orthogonal(void **state)
{
    (void)state;
    /* Orthogonal design, all d_i = d = 12: the three rules in closed form,
     * Z = |P y|^2, S = |y|^2 - Z, s2 = S/(m-r):
     *  SC:  Z/(1 + l d) = (r-2) S/(m-r+2)
     *  MM:  Z/(1 + l d) = r S/(m-r)
     *  ML2: 1 + l d = Z/(r s2)  (stationary point of the likelihood). */
    const int m = 12, N = 4;
    double A[12 * 4], y[12], beta[4], lam, shrink[4];
    int rank;
    for (int i = 0; i < m; i++) {
        A[i] = 1.0;
        A[i + 12] = (i % 2) ? 1.0 : -1.0;
        A[i + 24] = ((i / 2) % 2) ? 1.0 : -1.0;
        y[i] = 0.3 * A[i] - 0.7 * A[i + 12] + 0.2 * A[i + 24] +
               0.25 * sin(1.7 * i + 0.4);
    }
    /* column 3 = column 1 * column 2: all four mutually orthogonal */
    for (int i = 0; i < m; i++)
        A[i + 36] = A[i + 12] * A[i + 24];
    double G[16], g[4];
    normal_eq(m, N, A, m, y, 0.0, G, g);
    for (int a = 0; a < N; a++)
        for (int c = 0; c < N; c++)
            if (a != c)
                assert_true(fabs(G[a + 4 * c]) < 1e-14);
    double d = G[0], Z = 0.0, yy = 0.0;
    for (int a = 0; a < N; a++) {
        assert_close(G[a * 5], d, 1e-15);
        Z += g[a] * g[a] / d;
    }
    for (int i = 0; i < m; i++)
        yy += y[i] * y[i];
    double S = yy - Z, s2 = S / (m - N);
    double want[3] = {(Z / (2.0 * S / 10.0) - 1.0) / d,
                      (Z / (4.0 * S / 8.0) - 1.0) / d,
                      (Z / (4.0 * s2) - 1.0) / d};
    for (int rule = 0; rule < 3; rule++) {
        assert_int_equal(ebr_old(m, N, A, m, y, NULL, rule, 0.0, beta,
                                          &lam, &rank, shrink, NULL, NULL), 0);
        assert_int_equal(rank, 4);
        assert_close(lam, want[rule], 1e-10);
        for (int j = 0; j < N; j++) {
            assert_close(shrink[j], lam * d / (1 + lam * d), 1e-12);
            assert_close(beta[j], g[j] / d * shrink[j], 1e-11);
        }
    }
    /* lam_floor above lambda*: lambda hat = floor. */
    assert_int_equal(ebr_old(m, N, A, m, y, NULL, IGEA_REGRESS_EBR_SC, 100.0,
                                      beta, &lam, &rank, shrink, NULL, NULL), 0);
    assert_true(lam == 100.0);
    /* Positive-part rule: pure noise orthogonal to the design -> lambda 0,
     * beta 0 (full shrinkage to the prior mean). */
    double yn[12], w[12];
    for (int i = 0; i < m; i++)
        w[i] = sin(2.3 * i + 0.1);
    for (int i = 0; i < m; i++) {
        double p = 0.0;
        for (int a = 0; a < N; a++) {
            double at = 0.0;
            for (int t = 0; t < m; t++)
                at += A[t + 12 * a] * w[t];
            p += A[i + 12 * a] * at / 12.0;
        }
        yn[i] = w[i] - p + 1e-3 * A[i + 12];
    }
    assert_int_equal(ebr_old(m, N, A, m, yn, NULL, IGEA_REGRESS_EBR_SC, 0.0,
                                      beta, &lam, &rank, shrink, NULL, NULL), 0);
    assert_true(lam == 0.0);
    for (int j = 0; j < N; j++)
        assert_true(beta[j] == 0.0 && shrink[j] == 0.0);
}

static void test_ebr_prior_scale(void **state)
{
    (void)state;
    /* EBR(A, D_s) = D_s EBR(A D_s, I). */
    int lda = 22;
    double A[22 * 9], As[20 * 9], y[20], ds[9], b1[9], b2[9], l1, l2, p1[9],
        p2[9];
    int r1, r2;
    ebr_data(3e-5, lda, A, y);
    for (int j = 0; j < 9; j++) {
        ds[j] = 0.5 + 0.25 * j;
        for (int i = 0; i < 20; i++)
            As[i + 20 * j] = A[i + (size_t)lda * j] * ds[j];
    }
    assert_int_equal(ebr_old(20, 9, A, lda, y, ds, IGEA_REGRESS_EBR_SC, 0.0,
                                      b1, &l1, &r1, NULL, p1, NULL), 0);
    assert_int_equal(ebr_old(20, 9, As, 20, y, NULL, IGEA_REGRESS_EBR_SC, 0.0,
                                      b2, &l2, &r2, NULL, p2, NULL), 0);
    assert_int_equal(r1, r2);
    assert_close(l1, l2, 1e-12);
    for (int j = 0; j < 9; j++) {
        assert_close(b1[j], ds[j] * b2[j], 1e-10);
        assert_close(p1[j], ds[j] * p2[j], 1e-10);
    }
}

static void test_ebr_errors(void **state)
{
    (void)state;
    double A[20 * 9], y[20], b[9], lam = SENTINEL, sh[9], sp[9], sf[9],
        ds[9];
    int r = -3;
    ebr_data(1e-5, 20, A, y);
    for (int j = 0; j < 9; j++)
        ds[j] = 1.0;
    fill_sentinel(b, 9);
    fill_sentinel(sh, 9);
    fill_sentinel(sp, 9);
    fill_sentinel(sf, 9);
#define EBR(...) igea_regress_ebr(__VA_ARGS__)
    double cv[81], s2 = SENTINEL, rs[20];
    fill_sentinel(cv, 81);
    fill_sentinel(rs, 20);
    assert_int_equal(EBR(0, 9, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -1);
    assert_int_equal(EBR(20, 0, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -2);
    assert_int_equal(EBR(20, 9, NULL, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -3);
    assert_int_equal(EBR(20, 9, A, 19, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -4);
    assert_int_equal(EBR(20, 9, A, 20, NULL, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -5);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 3, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -8);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, -1, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -9);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, NAN, b, cv, 9, &lam, &r, &s2, rs, sh, sf), -9);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, 0, NULL, cv, 9, &lam, &r, &s2, rs, sh, sf), -10);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, 0, b, cv, 8, &lam, &r, &s2, rs, sh, sf), -12);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, NULL, &r, &s2, rs, sh, sf), -13);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, NULL, &s2, rs, sh, sf), -14);
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, NULL, rs, sh, sf), -15);
    ds[3] = 0.0;
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, ds, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf),
                     IGEA_ENONPOSITIVE);
    ds[3] = NAN;
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, ds, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf),
                     IGEA_ENONFINITE);
    ds[3] = 1.0;
    double sg[20];
    for (int i = 0; i < 20; i++)
        sg[i] = 1.0;
    sg[7] = -1.0;
    assert_int_equal(EBR(20, 9, A, 20, y, sg, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf),
                     IGEA_ENONPOSITIVE);
    y[4] = NAN;
    assert_int_equal(EBR(20, 9, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf),
                     IGEA_ENONFINITE);
    y[4] = 0.0;
    /* rank 2 < 3 */
    assert_int_equal(EBR(20, 2, A, 20, y, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf),
                     IGEA_ERANK);
    /* m == r: no residual degrees of freedom */
    double Q[9] = {1, 0, 0, 0, 2, 0, 0, 0, 3}, yq[3] = {1, 2, 3};
    assert_int_equal(EBR(3, 3, Q, 3, yq, NULL, NULL, 0, 0, b, cv, 9, &lam, &r, &s2, rs, sh, sf),
                     IGEA_EDOMAIN);
    assert_true(all_sentinel(cv, 81) && all_sentinel(rs, 20) && s2 == SENTINEL);
#undef EBR
    assert_true(all_sentinel(b, 9) && all_sentinel(sh, 9) &&
                all_sentinel(sp, 9) && all_sentinel(sf, 9) &&
                lam == SENTINEL && r == -3);
}

/* ---- ridge ---- */

static void test_ridge(void **state)
{
    (void)state;
    int lda = 19;
    double A[19 * 7], y[16], x[7], cov[49], ku, s2, res[16];
    longley_design(lda, A, y);
    /* Scale the columns to unit norm first (ridge is not scale-free). */
    double As[16 * 7];
    for (int j = 0; j < 7; j++) {
        double n = 0.0;
        for (int i = 0; i < 16; i++)
            n += A[i + lda * j] * A[i + lda * j];
        for (int i = 0; i < 16; i++)
            As[i + 16 * j] = A[i + lda * j] / sqrt(n);
    }
    double B[49], b[7], M[49], ref[7];
    const double k = 1e-4;
    assert_int_equal(igea_regress_ridge(16, 7, As, 16, y, NULL, NULL,
                                        IGEA_REGRESS_RIDGE_FIXED, k, x, cov, 7, &ku,
                                        &s2, res), 0);
    assert_true(ku == k);
    normal_eq(16, 7, As, 16, y, k, B, b);
    assert_true(gj_inverse(7, B, M));
    matvec(7, M, b, ref);
    for (int j = 0; j < 7; j++)
        assert_close(x[j], ref[j], 1e-8);
    assert_close(s2, longley_rsd * longley_rsd, 1e-9);
    /* cov = s2 M B0 M with B0 = A^T A */
    double B0[49], MB[49];
    normal_eq(16, 7, As, 16, y, 0.0, B0, b);
    for (int c = 0; c < 7; c++)
        matvec(7, M, B0 + 7 * c, MB + 7 * c);
    for (int a = 0; a < 7; a++) {
        double v = 0.0;
        for (int c = 0; c < 7; c++)
            v += MB[a + 7 * c] * M[c + 7 * a];
        assert_close(cov[a * 8], s2 * v, 1e-7);
    }
    /* HKB and LW in closed form from least squares (p = 7 = rank). */
    double xl[7], sl;
    int rk;
    assert_int_equal(igea_regress_ls(16, 7, As, 16, y, NULL, NULL, 0, xl, NULL, 1,
                                     &rk, &sl, NULL), 0);
    double nx = 0.0, nax = 0.0;
    for (int j = 0; j < 7; j++)
        nx += xl[j] * xl[j];
    for (int i = 0; i < 16; i++) {
        double v = 0.0;
        for (int j = 0; j < 7; j++)
            v += As[i + 16 * j] * xl[j];
        nax += v * v;
    }
    assert_int_equal(igea_regress_ridge(16, 7, As, 16, y, NULL, NULL, IGEA_REGRESS_RIDGE_HKB,
                                        0, x, NULL, 1, &ku, &s2, NULL), 0);
    assert_close(ku, 7 * sl / nx, 1e-9);
    assert_int_equal(igea_regress_ridge(16, 7, As, 16, y, NULL, NULL, IGEA_REGRESS_RIDGE_LW,
                                        0, x, NULL, 1, &ku, &s2, NULL), 0);
    assert_close(ku, 7 * sl / nax, 1e-9);
    /* GCV and LOO: the returned k is a local minimum of the criterion,
     * evaluated here independently from H = A M A^T. */
    for (int rule = IGEA_REGRESS_RIDGE_GCV; rule <= IGEA_REGRESS_RIDGE_LOO; rule++) {
        assert_int_equal(igea_regress_ridge(16, 7, As, 16, y, NULL, NULL, rule, 0, x,
                                            NULL, 1, &ku, &s2, NULL), 0);
        double crit[3];
        for (int t = 0; t < 3; t++) {
            double kk = ku * (t == 0 ? 1.0 : (t == 1 ? 1.05 : 1 / 1.05));
            normal_eq(16, 7, As, 16, y, kk, B, b);
            assert_true(gj_inverse(7, B, M));
            double rss = 0.0, tr = 0.0, press = 0.0;
            for (int i = 0; i < 16; i++) {
                double fit = 0.0, h = 0.0;
                for (int a = 0; a < 7; a++)
                    for (int c = 0; c < 7; c++) {
                        fit += As[i + 16 * a] * M[a + 7 * c] * b[c];
                        h += As[i + 16 * a] * M[a + 7 * c] * As[i + 16 * c];
                    }
                double e = y[i] - fit;
                rss += e * e;
                tr += h;
                press += (e / (1 - h)) * (e / (1 - h));
            }
            crit[t] = rule == IGEA_REGRESS_RIDGE_GCV ? 16 * rss / ((16 - tr) * (16 - tr))
                                             : press;
        }
        assert_true(crit[0] <= crit[1] * (1 + 1e-12));
        assert_true(crit[0] <= crit[2] * (1 + 1e-12));
    }
    /* Trace: k = 0 gives least squares; k = 1e-4 the fixed ridge. */
    double kg[2] = {0.0, 1e-4}, X[8 * 2], edf[2];
    assert_int_equal(igea_regress_ridge_trace(16, 7, As, 16, y, NULL, NULL, 2, kg, X,
                                              8, edf), 0);
    assert_close(edf[0], 7.0, 1e-12);
    assert_true(edf[1] < 7.0);
    assert_int_equal(igea_regress_ridge(16, 7, As, 16, y, NULL, NULL,
                                        IGEA_REGRESS_RIDGE_FIXED, 1e-4, x, NULL, 1, &ku,
                                        &s2, NULL), 0);
    for (int j = 0; j < 7; j++) {
        assert_close(X[j], xl[j], 1e-8);
        assert_close(X[8 + j], x[j], 1e-12);
    }
}

static void test_ridge_published_longley(void **state)
{
    (void)state;
    /* Published ridge constants for Longley (R, MASS::lm.ridge + select,
     * Venables & Ripley; output printed in Faraway, "Practical Regression
     * and Anova using R", ridge regression section, and in course notes): Employed ~ . gives
     * "modified HKB estimator is 0.004275357, modified L-W estimator is
     * 0.03229531"; GNP.deflator ~ . gives 0.006837 and 0.05267. MASS
     * centres the columns, scales them by sqrt(mean(x^2)), centres y and
     * uses s2 = RSS/(n-p-1), (p-2) instead of p, and for L-W a factor n;
     * so HKB_MASS = k_HKB (p-2)/p (n-p)/(n-p-1) and LW_MASS = that times n.
     * Column/row scalings of the NIST data (R stores some /10, /1000)
     * leave both unchanged. */
    for (int t = 0; t < 2; t++) {
        const int n = 16, p = 6;
        double X[16 * 6], y[16], x[6], kh, kl, s2;
        int ycol = t == 0 ? 0 : 1;
        int col = 0;
        for (int c = 0; c < 7; c++) {
            if (c == ycol)
                continue;
            double mean = 0.0, ms = 0.0;
            for (int i = 0; i < n; i++)
                mean += longley[i][c] / n;
            for (int i = 0; i < n; i++) {
                X[i + n * col] = longley[i][c] - mean;
                ms += X[i + n * col] * X[i + n * col] / n;
            }
            for (int i = 0; i < n; i++)
                X[i + n * col] /= sqrt(ms);
            col++;
        }
        double ym = 0.0;
        for (int i = 0; i < n; i++)
            ym += longley[i][ycol] / n;
        for (int i = 0; i < n; i++)
            y[i] = longley[i][ycol] - ym;
        assert_int_equal(igea_regress_ridge(n, p, X, n, y, NULL, NULL, IGEA_REGRESS_RIDGE_HKB,
                                            0, x, NULL, 1, &kh, &s2, NULL), 0);
        assert_int_equal(igea_regress_ridge(n, p, X, n, y, NULL, NULL, IGEA_REGRESS_RIDGE_LW,
                                            0, x, NULL, 1, &kl, &s2, NULL), 0);
        double f = (p - 2.0) / p * (n - p) / (n - p - 1.0);
        if (t == 0) {
            assert_digits(kh * f, 0.004275357, 7);
            assert_digits(kl * f * n, 0.03229531, 7);
        } else {
            assert_digits(kh * f, 0.006837, 4);
            assert_digits(kl * f * n, 0.05267, 4);
        }
    }
}

static void test_ridge_errors(void **state)
{
    (void)state;
    double A[6] = {1, 2, 3, 1, 0, 1}, y[3] = {1, 2, 2};
    double x[2], cov[4], ku = SENTINEL, s2 = SENTINEL, res[3], kg[1] = {0.1},
        X[2];
    fill_sentinel(x, 2);
    fill_sentinel(cov, 4);
    fill_sentinel(res, 3);
    fill_sentinel(X, 2);
#define RG(...) igea_regress_ridge(__VA_ARGS__)
    assert_int_equal(RG(0, 2, A, 3, y, NULL, NULL, 0, 1, x, cov, 2, &ku, &s2, res), -1);
    assert_int_equal(RG(3, 0, A, 3, y, NULL, NULL, 0, 1, x, cov, 2, &ku, &s2, res), -2);
    assert_int_equal(RG(3, 2, NULL, 3, y, NULL, NULL, 0, 1, x, cov, 2, &ku, &s2, res), -3);
    assert_int_equal(RG(3, 2, A, 1, y, NULL, NULL, 0, 1, x, cov, 2, &ku, &s2, res), -4);
    assert_int_equal(RG(3, 2, A, 3, NULL, NULL, NULL, 0, 1, x, cov, 2, &ku, &s2, res), -5);
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 5, 1, x, cov, 2, &ku, &s2, res), -8);
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 0, -1, x, cov, 2, &ku, &s2, res), -9);
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 0, 1, NULL, cov, 2, &ku, &s2, res), -10);
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 0, 1, x, cov, 1, &ku, &s2, res), -12);
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 0, 1, x, cov, 2, NULL, &s2, res), -13);
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 0, 1, x, cov, 2, &ku, NULL, res), -14);
    A[2] = NAN;
    assert_int_equal(RG(3, 2, A, 3, y, NULL, NULL, 0, 1, x, cov, 2, &ku, &s2, res),
                     IGEA_ENONFINITE);
    A[2] = 3;
    /* HKB needs residual degrees of freedom */
    double Q[4] = {1, 0, 0, 1}, yq[2] = {1, 1};
    assert_int_equal(RG(2, 2, Q, 2, yq, NULL, NULL, IGEA_REGRESS_RIDGE_HKB, 0, x, cov, 2, &ku,
                        &s2, res), IGEA_EDOMAIN);
#undef RG
    assert_int_equal(igea_regress_ridge_trace(3, 2, A, 3, y, NULL, NULL, 0, kg, X, 2,
                                              NULL), -8);
    assert_int_equal(igea_regress_ridge_trace(3, 2, A, 3, y, NULL, NULL, 1, NULL, X,
                                              2, NULL), -9);
    kg[0] = -1;
    assert_int_equal(igea_regress_ridge_trace(3, 2, A, 3, y, NULL, NULL, 1, kg, X, 2,
                                              NULL), -9);
    kg[0] = 1;
    assert_int_equal(igea_regress_ridge_trace(3, 2, A, 3, y, NULL, NULL, 1, kg, NULL,
                                              2, NULL), -10);
    assert_int_equal(igea_regress_ridge_trace(3, 2, A, 3, y, NULL, NULL, 1, kg, X, 1,
                                              NULL), -11);
    assert_true(all_sentinel(x, 2) && all_sentinel(cov, 4) &&
                all_sentinel(res, 3) && all_sentinel(X, 2) &&
                ku == SENTINEL && s2 == SENTINEL);
}

/* ---- PCE ---- */

static void test_pce(void **state)
{
    (void)state;
    /* A = [diag(3, 2, 1); 1 x 3 zero row], eigenvectors e_i, d = 9, 4, 1:
     * keeping 2 components gives x = (y1/3, y2/2, 0); eig_min = 0.5 keeps
     * all three (least squares). sigma2 = y4^2 / (4 - 3). */
    double A[5 * 3], y[4] = {3.0, -4.0, 0.5, 0.2}, x[3], cov[9], s2, res[4];
    int n;
    fill_nan(A, 15);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 4; i++)
            A[i + 5 * j] = (i == j) ? 3.0 - j : 0.0;
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 2, 0.0, x, cov, 3,
                                      &n, &s2, res), 0);
    assert_int_equal(n, 2);
    assert_close(x[0], 1.0, 1e-15);
    assert_close(x[1], -2.0, 1e-15);
    assert_true(x[2] == 0.0);
    assert_close(s2, 0.04, 1e-13);
    assert_close(cov[0], 0.04 / 9, 1e-13);
    assert_close(cov[4], 0.04 / 4, 1e-13);
    assert_close_abs(cov[8], 0.0, 0, 1e-30);
    assert_close(res[2], 0.5, 1e-15);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 0, 0.5, x, NULL, 1,
                                      &n, &s2, NULL), 0);
    assert_int_equal(n, 3);
    assert_close(x[2], 0.5, 1e-15);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 0, 5.0, x, NULL, 1,
                                      &n, &s2, NULL), 0);
    assert_int_equal(n, 1);
    assert_true(x[1] == 0.0);
    /* errors */
    double xs[3];
    fill_sentinel(xs, 3);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, -1, 0, xs, NULL, 1,
                                      &n, &s2, NULL), -8);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 0, 0, xs, NULL, 1,
                                      &n, &s2, NULL), -9);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 1, 0, NULL, NULL, 1,
                                      &n, &s2, NULL), -10);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 1, 0, xs, cov, 2,
                                      &n, &s2, NULL), -12);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 1, 0, xs, NULL, 1,
                                      NULL, &s2, NULL), -13);
    assert_int_equal(igea_regress_pce(4, 3, A, 5, y, NULL, NULL, 1, 0, xs, NULL, 1,
                                      &n, NULL, NULL), -14);
    assert_int_equal(igea_regress_pce(4, 3, A, 4, y, NULL, NULL, 1, 0, xs, NULL, 1,
                                      &n, &s2, NULL), IGEA_ENONFINITE - 0 * 4);
    assert_true(all_sentinel(xs, 3));
}

/* ---- Bayes ---- */

static void test_bayes(void **state)
{
    (void)state;
    /* Singular design (METHODS 4.2) + SPD prior: closed form
     * cov = (A^T W A + P^-1)^-1, x = cov (A^T W y + P^-1 mu). */
    int lda = 21;
    double A[21 * 9], y[20], sg[20], mu[9], P[10 * 9], x[9], cov[81],
        res[20];
    ebr_data(2e-5, lda, A, y);
    fill_nan(P, 90);
    for (int i = 0; i < 20; i++)
        sg[i] = 1e-5 * (1.0 + 0.05 * i);
    for (int j = 0; j < 9; j++) {
        mu[j] = 1e-5 * (j - 4);
        for (int i = 0; i < 9; i++)
            P[i + 10 * j] = 1e-8 * (i == j ? 2.0 + 0.1 * i : 0.3 / (1 + abs(i - j)));
    }
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, P, 10, x,
                                        cov, 9, res), 0);
    double Aw[20 * 9], yw[20], B[81], b[9], Pi[81], Pd[81], C[81], rhs[9],
        pm[9], ref[9];
    for (int i = 0; i < 20; i++) {
        yw[i] = y[i] / sg[i];
        for (int j = 0; j < 9; j++)
            Aw[i + 20 * j] = A[i + lda * j] / sg[i];
    }
    normal_eq(20, 9, Aw, 20, yw, 0.0, B, b);
    for (int j = 0; j < 9; j++)
        for (int i = 0; i < 9; i++)
            Pd[i + 9 * j] = P[(i > j ? i : j) + 10 * (i > j ? j : i)];
    assert_true(gj_inverse(9, Pd, Pi));
    for (int k = 0; k < 81; k++)
        B[k] += Pi[k];
    assert_true(gj_inverse(9, B, C));
    matvec(9, Pi, mu, pm);
    for (int j = 0; j < 9; j++)
        rhs[j] = b[j] + pm[j];
    matvec(9, C, rhs, ref);
    for (int j = 0; j < 9; j++) {
        assert_close(x[j], ref[j], 1e-8);
        for (int i = 0; i < 9; i++)
            assert_close_abs(cov[i + 9 * j], C[i + 9 * j], 1e-7,
                             1e-9 * sqrt(C[i * 10] * C[j * 10]));
    }
    double r0 = y[0];
    for (int j = 0; j < 9; j++)
        r0 -= A[lda * j] * x[j];
    assert_close_abs(res[0], r0, 1e-9, 1e-14);
    /* errors */
    double xs[9];
    fill_sentinel(xs, 9);
    /* no prior covariance: the identity (diag(spec^2) without a spec) */
    double xI[9], xN[9], PI[81] = {0};
    for (int k = 0; k < 9; k++)
        PI[k * 10] = 1.0;
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, PI, 9, xI,
                                        NULL, 9, NULL), 0);
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, NULL, 0, xN,
                                        NULL, 9, NULL), 0);
    for (int k = 0; k < 9; k++)
        assert_true(xN[k] == xI[k]);
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, P, 8, xs,
                                        NULL, 9, NULL), -10);
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, P, 10, NULL,
                                        NULL, 9, NULL), -11);
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, P, 10, xs,
                                        cov, 8, NULL), -13);
    double Pbad[81];
    for (int k = 0; k < 81; k++)
        Pbad[k] = (k % 10 == 0) ? 1.0 : 0.0;
    Pbad[4 * 10] = -1.0;
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, Pbad, 9, xs,
                                        NULL, 9, NULL), IGEA_ESINGULAR);
    mu[2] = NAN;
    assert_int_equal(igea_regress_bayes(20, 9, A, lda, y, sg, NULL, mu, P, 10, xs,
                                        NULL, 9, NULL), IGEA_ENONFINITE);
    assert_true(all_sentinel(xs, 9));
}

/* ---- diagnostics ---- */

static void test_collinearity(void **state)
{
    (void)state;
    /* METHODS 4.2: eigenvalues (17.5 +- sqrt(231.25))/2 (x2), 10, 5, 2.5,
     * 0, 0; coefficients 0, 1, 5, 6, 7, 8 are prior-determined; VIF of
     * k_A1 = 7.5 * 7.5/50 = 1.125, of eta = 1. */
    int lda = 24;
    double A[24 * 9], y[20], cond[2], eig[9], V[10 * 9], vif[9], sd[9];
    int rank, pd[9];
    ebr_data(0.0, lda, A, y);
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, NULL, NULL, NULL, 0,
                                               cond, &rank, eig, V, 10, vif,
                                               sd, pd), 0);
    assert_int_equal(rank, 7);
    double hi = (17.5 + sqrt(231.25)) / 2, lo = (17.5 - sqrt(231.25)) / 2;
    const double ref[7] = {hi, hi, 10, 5, 2.5, lo, lo};
    for (int i = 0; i < 7; i++) {
        assert_close(eig[i], ref[i], 1e-13);
        assert_close(sd[i], 1.0 / sqrt(ref[i]), 1e-13);
    }
    assert_true(eig[7] < 1e-25 && eig[8] < 1e-25);
    assert_true(isinf(sd[7]) && isinf(sd[8]));
    assert_close(cond[1], sqrt(hi / lo), 1e-12);
    assert_true(cond[0] > 1e14);
    const int pd_ref[9] = {1, 1, 0, 0, 0, 1, 1, 1, 1};
    for (int j = 0; j < 9; j++) {
        assert_int_equal(pd[j], pd_ref[j]);
        if (pd_ref[j])
            assert_true(isinf(vif[j]));
    }
    assert_close(vif[2], 1.125, 1e-12);
    assert_close(vif[3], 1.125, 1e-12);
    assert_close(vif[4], 1.0, 1e-12);
    /* the null space spans n1 and n2 */
    const double n1[9] = {-1, 0, 0, 0, 0, 1, 0, 0, -1};
    const double n2[9] = {0, -1, 0, 0, 0, 0, 1, 1, 0};
    for (int t = 0; t < 2; t++) {
        const double *n = t ? n2 : n1;
        double p = 0.0;
        for (int c = 7; c < 9; c++) {
            double dt = 0.0;
            for (int j = 0; j < 9; j++)
                dt += V[j + 10 * c] * n[j];
            p += dt * dt;
        }
        assert_close(p, 3.0, 1e-12);
    }
    /* with y: sd of the combinations scale with s = sqrt(RSS/(m-r)) */
    ebr_data(4e-5, lda, A, y);
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 0, cond,
                                               &rank, eig, NULL, 1, NULL, sd,
                                               NULL), 0);
    double s = sqrt(12.5 * 16e-10 / 13.0);
    assert_close(sd[0], s / sqrt(hi), 1e-9);
    /* errors */
    double cs[2] = {SENTINEL, SENTINEL};
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 2, cs,
                                               &rank, eig, V, 10, vif, sd, pd),
                     -8);
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 0, NULL,
                                               &rank, eig, V, 10, vif, sd, pd),
                     -9);
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 0, cs,
                                               NULL, eig, V, 10, vif, sd, pd),
                     -10);
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 0, cs,
                                               &rank, NULL, V, 10, vif, sd, pd),
                     -11);
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 0, cs,
                                               &rank, eig, V, 8, vif, sd, pd),
                     -13);
    A[3] = INFINITY;
    assert_int_equal(igea_regress_collinearity(20, 9, A, lda, y, NULL, NULL, 0, cs,
                                               &rank, eig, V, 10, vif, sd, pd),
                     IGEA_ENONFINITE);
    assert_true(cs[0] == SENTINEL && cs[1] == SENTINEL);
}

/* ---- fewer rows than terms, scaling, sigma range ---------------------- */

/* Solve the n x n SPD system M u = b (n <= 8) by Cholesky, in the test's
 * own arithmetic (M is overwritten). */
static void spd_solve(int n, double *M, double *b)
{
    for (int j = 0; j < n; j++) {
        double d = M[j + j * n];
        for (int k = 0; k < j; k++)
            d -= M[j + k * n] * M[j + k * n];
        assert_true(d > 0.0);
        M[j + j * n] = sqrt(d);
        for (int i = j + 1; i < n; i++) {
            double v = M[i + j * n];
            for (int k = 0; k < j; k++)
                v -= M[i + k * n] * M[j + k * n];
            M[i + j * n] = v / M[j + j * n];
        }
    }
    for (int i = 0; i < n; i++) {
        double v = b[i];
        for (int k = 0; k < i; k++)
            v -= M[i + k * n] * b[k];
        b[i] = v / M[i + i * n];
    }
    for (int i = n - 1; i >= 0; i--) {
        double v = b[i];
        for (int k = i + 1; k < n; k++)
            v -= M[k + i * n] * b[k];
        b[i] = v / M[i + i * n];
    }
}

/* x = A^T (A A^T + k I)^-1 y for the m x N matrix A (ld m), m <= 8: the
 * minimum-norm least-squares solution at k = 0 (full row rank), ridge
 * x(k) = (A^T A + k I)^-1 A^T y otherwise (push-through identity). */
static void wide_closed_form(int m, int N, const double *A, const double *y,
                             double k, double *x)
{
    double M[64], u[8];
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < m; j++) {
            double v = 0.0;
            for (int c = 0; c < N; c++)
                v += A[i + c * m] * A[j + c * m];
            M[i + j * m] = v + (i == j ? k : 0.0);
        }
        u[i] = y[i];
    }
    spd_solve(m, M, u);
    for (int c = 0; c < N; c++) {
        x[c] = 0.0;
        for (int i = 0; i < m; i++)
            x[c] += A[i + c * m] * u[i];
    }
}

/* A 2 x 40 design with entries of mixed sign, and its y. */
static void wide_2x40(double *A, double *y)
{
    for (int j = 0; j < 40; j++) {
        A[0 + 2 * j] = sin(0.3 * j + 0.1);
        A[1 + 2 * j] = cos(0.7 * j) + 0.01 * j;
    }
    y[0] = 1.5;
    y[1] = -0.25;
}

static void test_wide_ls_pce_ridge(void **state)
{
    (void)state;
    enum { M = 2, N = 40 };
    double A[M * N], y[M], want[N], x[N], cov[N * N], res[M], ku, s2;
    int rank, nused;
    wide_2x40(A, y);
    /* LS: the minimum-norm solution, an exact fit. */
    wide_closed_form(M, N, A, y, 0.0, want);
    fill_sentinel(cov, N * N);
    assert_int_equal(igea_regress_ls(M, N, A, M, y, NULL, NULL, 0, x, cov, N, &rank,
                                     &s2, res), 0);
    assert_int_equal(rank, 2);
    assert_true(s2 == 0.0);
    for (int j = 0; j < N; j++)
        assert_close_abs(x[j], want[j], 1e-12, 1e-14);
    for (int i = 0; i < M; i++)
        assert_close_abs(res[i], 0.0, 0.0, 1e-13);
    /* PCE keeping every component: the same solution. */
    assert_int_equal(igea_regress_pce(M, N, A, M, y, NULL, NULL, N, 0.0, x, cov, N,
                                      &nused, &s2, res), 0);
    assert_int_equal(nused, 2);
    for (int j = 0; j < N; j++)
        assert_close_abs(x[j], want[j], 1e-12, 1e-14);
    /* Ridge, fixed k, every scratch path (cov and residual requested). */
    const double ks[3] = {0.0, 0.3, 25.0};
    for (int t = 0; t < 3; t++) {
        wide_closed_form(M, N, A, y, ks[t], want);
        fill_sentinel(cov, N * N);
        assert_int_equal(igea_regress_ridge(M, N, A, M, y, NULL, NULL, IGEA_REGRESS_RIDGE_FIXED,
                                            ks[t], x, cov, N, &ku, &s2, res), 0);
        assert_true(ku == ks[t]);
        assert_true(s2 == 0.0); /* m == r: no residual variance */
        for (int j = 0; j < N; j++)
            assert_close_abs(x[j], want[j], 1e-11, 1e-14);
        for (int j = 0; j < N * N; j++)
            assert_true(cov[j] == 0.0);
        for (int i = 0; i < M; i++) {
            double f = y[i];
            for (int j = 0; j < N; j++)
                f -= A[i + M * j] * want[j];
            assert_close_abs(res[i], f, 1e-10, 1e-13);
        }
    }
    /* Weighted: diag(1/sigma) A and y / sigma in the closed form. */
    double sg[M] = {0.5, 4.0}, Aw[M * N], yw[M];
    for (int j = 0; j < N; j++)
        for (int i = 0; i < M; i++)
            Aw[i + M * j] = A[i + M * j] / sg[i];
    for (int i = 0; i < M; i++)
        yw[i] = y[i] / sg[i];
    wide_closed_form(M, N, Aw, yw, 0.7, want);
    assert_int_equal(igea_regress_ridge(M, N, A, M, y, sg, NULL, IGEA_REGRESS_RIDGE_FIXED, 0.7,
                                        x, NULL, N, &ku, &s2, NULL), 0);
    for (int j = 0; j < N; j++)
        assert_close_abs(x[j], want[j], 1e-11, 1e-14);
    /* HKB and LW need residual degrees of freedom: refused, untouched. */
    for (int rule = IGEA_REGRESS_RIDGE_HKB; rule <= IGEA_REGRESS_RIDGE_LW; rule++) {
        fill_sentinel(x, N);
        fill_sentinel(cov, N * N);
        fill_sentinel(res, M);
        ku = s2 = SENTINEL;
        assert_int_equal(igea_regress_ridge(M, N, A, M, y, NULL, NULL, rule, 0.0, x,
                                            cov, N, &ku, &s2, res), IGEA_EDOMAIN);
        assert_true(all_sentinel(x, N) && all_sentinel(cov, N * N) &&
                    all_sentinel(res, M) && ku == SENTINEL && s2 == SENTINEL);
    }
    /* GCV and LOO: the x returned is the ridge solution at the k returned. */
    for (int rule = IGEA_REGRESS_RIDGE_GCV; rule <= IGEA_REGRESS_RIDGE_LOO; rule++) {
        int st = igea_regress_ridge(M, N, A, M, y, NULL, NULL, rule, 0.0, x, cov, N,
                                    &ku, &s2, res);
        assert_int_equal(st, 0);
        assert_true(ku >= 0.0 && isfinite(ku));
        wide_closed_form(M, N, A, y, ku, want);
        for (int j = 0; j < N; j++)
            assert_close_abs(x[j], want[j], 1e-9, 1e-13);
    }
    /* Ridge trace with m < N. */
    double kk[3] = {0.0, 0.3, 25.0}, X[N * 3], edf[3];
    assert_int_equal(igea_regress_ridge_trace(M, N, A, M, y, NULL, NULL, 3, kk, X, N,
                                              edf), 0);
    for (int t = 0; t < 3; t++) {
        wide_closed_form(M, N, A, y, kk[t], want);
        for (int j = 0; j < N; j++)
            assert_close_abs(X[j + N * t], want[j], 1e-11, 1e-14);
        /* edf = tr(G (G + kI)^-1), G = A A^T (2 x 2) */
        double g11 = 0, g12 = 0, g22 = 0;
        for (int j = 0; j < N; j++) {
            g11 += A[2 * j] * A[2 * j];
            g12 += A[2 * j] * A[2 * j + 1];
            g22 += A[2 * j + 1] * A[2 * j + 1];
        }
        double a = g11 + kk[t], d = g22 + kk[t], det = a * d - g12 * g12;
        double tr = (g11 * d - g12 * g12 + g22 * a - g12 * g12) / det;
        assert_close(edf[t], tr, 1e-12);
    }
}

static void test_wide_1x3(void **state)
{
    (void)state;
    /* The driver's reproducer: S = [1 2 3], y = 0.5. */
    double A[3] = {1, 2, 3}, y[1] = {0.5}, x[3], cov[9], res[1], ku, s2;
    int rank, nused;
    assert_int_equal(igea_regress_ls(1, 3, A, 1, y, NULL, NULL, 0, x, cov, 3, &rank,
                                     &s2, res), 0);
    for (int j = 0; j < 3; j++)
        assert_close(x[j], A[j] * 0.5 / 14.0, 1e-14);
    for (int rule = IGEA_REGRESS_RIDGE_FIXED; rule <= IGEA_REGRESS_RIDGE_LOO; rule++) {
        int st = igea_regress_ridge(1, 3, A, 1, y, NULL, NULL, rule, 2.0, x, cov, 3,
                                    &ku, &s2, res);
        if (rule == IGEA_REGRESS_RIDGE_HKB || rule == IGEA_REGRESS_RIDGE_LW) {
            assert_int_equal(st, IGEA_EDOMAIN);
            continue;
        }
        assert_int_equal(st, 0);
        if (rule == IGEA_REGRESS_RIDGE_FIXED)
            assert_true(ku == 2.0);
        /* x = a y / (|a|^2 + k) */
        for (int j = 0; j < 3; j++)
            assert_close(x[j], A[j] * 0.5 / (14.0 + ku), 1e-12);
    }
    assert_int_equal(igea_regress_pce(1, 3, A, 1, y, NULL, NULL, 3, 0.0, x, cov, 3,
                                      &nused, &s2, res), 0);
    assert_int_equal(nused, 1);
    for (int j = 0; j < 3; j++)
        assert_close(x[j], A[j] * 0.5 / 14.0, 1e-14);
    /* Bayes with P = I, mu = 0: x = a y / (|a|^2 + 1),
     * cov = I - a a^T / (|a|^2 + 1). */
    double P[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    assert_int_equal(igea_regress_bayes(1, 3, A, 1, y, NULL, NULL, NULL, P, 3, x, cov,
                                        3, res), 0);
    for (int j = 0; j < 3; j++) {
        assert_close(x[j], A[j] * 0.5 / 15.0, 1e-14);
        for (int i = 0; i < 3; i++)
            assert_close_abs(cov[i + 3 * j], (i == j) - A[i] * A[j] / 15.0,
                             1e-13, 1e-15);
    }
    /* EBR needs rank >= 3. */
    double lam = SENTINEL, beta[3];
    fill_sentinel(beta, 3);
    assert_int_equal(ebr_old(1, 3, A, 1, y, NULL, IGEA_REGRESS_EBR_MM, 0.0,
                                      beta, &lam, &rank, NULL, NULL, NULL),
                     IGEA_ERANK);
    assert_true(all_sentinel(beta, 3) && lam == SENTINEL);
    double cs[2], eig[3], V[9], vif[3], sd[3];
    int pd[3];
    assert_int_equal(igea_regress_collinearity(1, 3, A, 1, NULL, NULL, NULL, 0, cs,
                                               &rank, eig, V, 3, vif, sd, pd),
                     0);
    assert_int_equal(rank, 1);
    assert_close(eig[0], 14.0, 1e-14);
    assert_true(eig[1] == 0.0 && eig[2] == 0.0);
    assert_true(isinf(cs[0]));
    assert_close(sd[0], 1.0 / sqrt(14.0), 1e-14);
    for (int j = 0; j < 3; j++)
        assert_int_equal(pd[j], 1);
}

static void test_wide_bayes_ebr_collinearity(void **state)
{
    (void)state;
    enum { M = 2, N = 40 };
    double A[M * N], y[M], want[N], x[N], cov[N * N], res[M];
    wide_2x40(A, y);
    /* Bayes, P = I: x = A^T (A A^T + I)^-1 y, cov = I - A^T (AA^T + I)^-1 A. */
    static double P[N * N];
    for (int j = 0; j < N * N; j++)
        P[j] = (j % (N + 1)) == 0;
    wide_closed_form(M, N, A, y, 1.0, want);
    assert_int_equal(igea_regress_bayes(M, N, A, M, y, NULL, NULL, NULL, P, N, x, cov,
                                        N, res), 0);
    for (int j = 0; j < N; j++)
        assert_close_abs(x[j], want[j], 1e-12, 1e-14);
    for (int c = 0; c < N; c += 7) {
        /* column c of cov: e_c - A^T (AA^T + I)^-1 A e_c */
        double e[M] = {A[M * c], A[1 + M * c]}, col[N];
        wide_closed_form(M, N, A, e, 1.0, col);
        for (int j = 0; j < N; j++)
            assert_close_abs(cov[j + N * c], (j == c) - col[j], 1e-12, 1e-14);
    }
    /* Collinearity: d_1, d_2 the eigenvalues of A A^T, then zeros. */
    double cs[2], eig[N], V[N * N], vif[N], sd[N];
    int rank, pd[N];
    assert_int_equal(igea_regress_collinearity(M, N, A, M, NULL, NULL, NULL, 0, cs,
                                               &rank, eig, V, N, vif, sd, pd), 0);
    double g11 = 0, g12 = 0, g22 = 0;
    for (int j = 0; j < N; j++) {
        g11 += A[2 * j] * A[2 * j];
        g12 += A[2 * j] * A[2 * j + 1];
        g22 += A[2 * j + 1] * A[2 * j + 1];
    }
    double h = 0.5 * (g11 + g22), q = sqrt(0.25 * (g11 - g22) * (g11 - g22) + g12 * g12);
    assert_int_equal(rank, 2);
    assert_close(eig[0], h + q, 1e-13);
    assert_close(eig[1], h - q, 1e-12);
    for (int j = 2; j < N; j++)
        assert_true(eig[j] == 0.0);
    assert_true(isinf(cs[0]));
    assert_close(cs[1], sqrt((h + q) / (h - q)), 1e-12);
    /* EBR with m < N: a 5 x 8 design of rank 3 (m > r). beta is the
     * ridge solution at k = 1 / lambda. */
    enum { M5 = 5, N8 = 8 };
    double B[M5 * N8], yb[M5], bt[N8], lam, sh[N8], sp[N8], sf[N8];
    int r5;
    for (int j = 0; j < N8; j++)
        for (int i = 0; i < M5; i++) {
            double b0 = 1.0 + i, b1 = cos(1.3 * i), b2 = (i * i) % 3 - 1.0;
            B[i + M5 * j] = b0 * sin(0.4 * j + 0.2) + b1 * (j - 3.5) +
                            b2 * cos(0.9 * j);
        }
    for (int i = 0; i < M5; i++)
        yb[i] = 0.3 * i - 0.5 + 0.1 * (i % 2);
    assert_int_equal(ebr_old(M5, N8, B, M5, yb, NULL, IGEA_REGRESS_EBR_MM, 0.5,
                                      bt, &lam, &r5, sh, sp, sf), 0);
    assert_int_equal(r5, 3);
    assert_true(lam >= 0.5 && isfinite(lam));
    /* ridge at k = 1/lam on a rank-deficient design: (A^T A + kI)^-1 A^T y
     * = A^T (A A^T + kI)^-1 y still holds for k > 0. */
    double wb[N8];
    wide_closed_form(M5, N8, B, yb, 1.0 / lam, wb);
    for (int j = 0; j < N8; j++)
        assert_close_abs(bt[j], wb[j], 1e-9, 1e-12);
    for (int j = 0; j < N8; j++)
        assert_true(isfinite(sp[j]) && isfinite(sf[j]) && isfinite(sh[j]));
}

/* A = [1 0; 0 1; 1 1; 1 -1; 2 1; 0 3], y with a residual. */
static const double small_A[12] = {1, 0, 1, 1, 2, 0, 0, 1, 1, -1, 1, 3};
static const double small_y[6] = {1.0, 2.1, 2.9, -1.2, 4.1, 5.8};

static void test_scaled_designs(void **state)
{
    (void)state;
    double A[12], x0[2], x[2], cov[4], res[6], s2, ku, s20;
    int rank;
    /* LS on A * 1e-300: x = 1e300 x(A), an exact change of units. */
    assert_int_equal(igea_regress_ls(6, 2, small_A, 6, small_y, NULL, NULL, 0, x0,
                                     NULL, 2, &rank, &s20, NULL), 0);
    for (int i = 0; i < 12; i++)
        A[i] = small_A[i] * 1e-300;
    assert_int_equal(igea_regress_ls(6, 2, A, 6, small_y, NULL, NULL, 0, x, NULL, 2,
                                     &rank, &s2, res), 0);
    assert_close(x[0], x0[0] * 1e300, 1e-13);
    assert_close(x[1], x0[1] * 1e300, 1e-13);
    assert_close(s2, s20, 1e-12);
    /* ... whose covariance (~1e600) is not representable: a status. */
    fill_sentinel(cov, 4);
    fill_sentinel(x, 2);
    s2 = SENTINEL;
    assert_int_equal(igea_regress_ls(6, 2, A, 6, small_y, NULL, NULL, 0, x, cov, 2,
                                     &rank, &s2, res), IGEA_EOVERFLOW);
    assert_true(all_sentinel(cov, 4) && all_sentinel(x, 2) && s2 == SENTINEL);
    /* Ridge k = 0 (minimum-norm LS) on A * 1e-300: d_i = s_i^2 underflows,
     * s_i / (d_i + k) must not. */
    assert_int_equal(igea_regress_ridge(6, 2, A, 6, small_y, NULL, NULL,
                                        IGEA_REGRESS_RIDGE_FIXED, 0.0, x, NULL, 2, &ku,
                                        &s2, NULL), 0);
    assert_close(x[0], x0[0] * 1e300, 1e-12);
    assert_close(x[1], x0[1] * 1e300, 1e-12);
    /* Lawless-Wang's k = r s^2 / |A x_LS|^2 does not depend on the scale
     * of A: k(A * 1e-300) = k(A), and x = (A^T A + k I)^-1 A^T y is then
     * 1e-300 A0^T y / k to a relative 1e-600. */
    double fit[6], nf = 0.0;
    for (int i = 0; i < 6; i++) {
        fit[i] = small_A[i] * x0[0] + small_A[i + 6] * x0[1];
        nf += fit[i] * fit[i];
    }
    double klw = 2.0 * s20 / nf;
    assert_int_equal(igea_regress_ridge(6, 2, A, 6, small_y, NULL, NULL,
                                        IGEA_REGRESS_RIDGE_LW, 0.0, x, NULL, 2, &ku,
                                        &s2, res), 0);
    assert_close(ku, klw, 1e-12);
    for (int j = 0; j < 2; j++) {
        double aty = 0.0;
        for (int i = 0; i < 6; i++)
            aty += small_A[i + 6 * j] * small_y[i];
        assert_close(x[j], 1e-300 * aty / klw, 1e-12);
    }
    /* HKB, GCV and LOO on A * 1e-300 choose k ~ 1e-600: not a double, so a
     * status, never NaN with status 0; outputs untouched. */
    for (int rule = IGEA_REGRESS_RIDGE_HKB; rule <= IGEA_REGRESS_RIDGE_LOO; rule++) {
        if (rule == IGEA_REGRESS_RIDGE_LW)
            continue;
        fill_sentinel(x, 2);
        fill_sentinel(res, 6);
        ku = s2 = SENTINEL;
        int st = igea_regress_ridge(6, 2, A, 6, small_y, NULL, NULL, rule, 0.0, x,
                                    NULL, 2, &ku, &s2, res);
        assert_int_equal(st, IGEA_EOVERFLOW);
        assert_true(all_sentinel(x, 2) && all_sentinel(res, 6) &&
                    ku == SENTINEL && s2 == SENTINEL);
    }
    /* HKB on A and on A * 2^-40 (within range): k scales by 2^-80 and x by
     * 2^40 exactly in exact arithmetic. */
    double k0, xa[2];
    assert_int_equal(igea_regress_ridge(6, 2, small_A, 6, small_y, NULL, NULL,
                                        IGEA_REGRESS_RIDGE_HKB, 0.0, xa, NULL, 2, &k0,
                                        &s20, NULL), 0);
    /* HKB closed form: k = r s^2 / |x_LS|^2 */
    assert_close(k0, 2.0 * s20 / (x0[0] * x0[0] + x0[1] * x0[1]), 1e-12);
    for (int i = 0; i < 12; i++)
        A[i] = small_A[i] * 0x1p-40;
    assert_int_equal(igea_regress_ridge(6, 2, A, 6, small_y, NULL, NULL,
                                        IGEA_REGRESS_RIDGE_HKB, 0.0, x, NULL, 2, &ku,
                                        &s2, NULL), 0);
    assert_close(ku, k0 * 0x1p-80, 1e-12);
    assert_close(x[0], xa[0] * 0x1p40, 1e-12);
    assert_close(x[1], xa[1] * 0x1p40, 1e-12);
}

static void test_scaled_column_ridge(void **state)
{
    (void)state;
    /* Three terms, the third column multiplied by 1e300: relative to
     * s_1 ~ 1e300 the other singular values (~1) are below the rank cut
     * max(m, N) eps s_1, so the numerical rank is 1 and the estimable
     * direction is e_3. HKB then asks k = s^2 / x_LS^2 ~ 1e600: a status
     * (was k = NaN with status 0). Lawless-Wang's k = s^2 / z_1^2, with z_1
     * = u_1^T y, u_1 the unit third column, is representable. */
    double As[18], y[6] = {1.0, 2.1, 2.9, -1.2, 4.1, 5.8}, c3[6], nc = 0.0;
    for (int i = 0; i < 6; i++) {
        As[i] = small_A[i];
        As[6 + i] = small_A[6 + i];
        c3[i] = 1.0 + 0.5 * i * i - 0.1 * i;
        As[12 + i] = c3[i] * 1e300;
        nc += c3[i] * c3[i];
    }
    nc = sqrt(nc);
    double z1 = 0.0, yy = 0.0;
    for (int i = 0; i < 6; i++) {
        z1 += c3[i] / nc * y[i];
        yy += y[i] * y[i];
    }
    double s2 = (yy - z1 * z1) / 5.0, klw = s2 / (z1 * z1);
    double x[3], cov[9], res[6], ku, s2o;
    fill_sentinel(x, 3);
    fill_sentinel(cov, 9);
    ku = s2o = SENTINEL;
    assert_int_equal(igea_regress_ridge(6, 3, As, 6, y, NULL, NULL, IGEA_REGRESS_RIDGE_HKB,
                                        0.0, x, cov, 3, &ku, &s2o, res),
                     IGEA_EOVERFLOW);
    assert_true(all_sentinel(x, 3) && all_sentinel(cov, 9) && ku == SENTINEL &&
                s2o == SENTINEL);
    assert_int_equal(igea_regress_ridge(6, 3, As, 6, y, NULL, NULL, IGEA_REGRESS_RIDGE_LW,
                                        0.0, x, cov, 3, &ku, &s2o, res), 0);
    assert_close(s2o, s2, 1e-10);
    assert_close(ku, klw, 1e-10);
    assert_close(x[2], z1 / (nc * 1e300), 1e-12); /* s_1 >> k: LS */
    assert_true(fabs(x[0]) < 1e-290 && fabs(x[1]) < 1e-290);
    for (int j = 0; j < 9; j++)
        assert_true(isfinite(cov[j]));
    /* GCV and LOO search k around d_1 ~ 1e600: a k that is not a double is
     * a status; whatever is returned with status 0 is finite. */
    for (int rule = IGEA_REGRESS_RIDGE_GCV; rule <= IGEA_REGRESS_RIDGE_LOO; rule++) {
        fill_sentinel(x, 3);
        ku = SENTINEL;
        int st = igea_regress_ridge(6, 3, As, 6, y, NULL, NULL, rule, 0.0, x, cov, 3,
                                    &ku, &s2o, res);
        if (st == 0)
            assert_true(isfinite(ku) && isfinite(x[0]) && isfinite(x[1]) &&
                        isfinite(x[2]));
        else {
            assert_int_equal(st, IGEA_EOVERFLOW);
            assert_true(all_sentinel(x, 3) && ku == SENTINEL);
        }
    }
}

static void test_ebr_scaled(void **state)
{
    (void)state;
    /* The EBR test vector design scaled by 1e-300: beta ~ 1e300 beta0 but
     * lambda ~ 1e600 lambda0, not a double: a status, outputs untouched
     * (was NaN estimates with status 0). A scale of 2^-60 is solved
     * exactly as a change of units. */
    enum { M = 30, N = 4 };
    double A[M * N], As[M * N], y[M];
    for (int i = 0; i < M; i++) {
        double t = (i + 0.5) / M;
        A[i] = 1.0;
        A[i + M] = t;
        A[i + 2 * M] = t * t;
        A[i + 3 * M] = sin(6.0 * t);
        y[i] = 0.2 + 0.5 * t - 0.3 * t * t + 0.05 * sin(6.0 * t) +
               0.02 * cos(37.0 * i);
    }
    double b0[N], l0, sp0[N], sf0[N];
    int r0;
    assert_int_equal(ebr_old(M, N, A, M, y, NULL, IGEA_REGRESS_EBR_MM, 0.0, b0,
                                      &l0, &r0, NULL, sp0, sf0), 0);
    assert_true(l0 > 0.0);
    for (int rule = IGEA_REGRESS_EBR_SC; rule <= IGEA_REGRESS_EBR_ML2; rule++) {
        for (int i = 0; i < M * N; i++)
            As[i] = A[i] * 1e-300;
        double b[N], lam = SENTINEL, sp[N], sf[N], sh[N];
        int rank = -7;
        fill_sentinel(b, N);
        fill_sentinel(sp, N);
        int st = ebr_old(M, N, As, M, y, NULL, rule, 0.0, b, &lam,
                                  &rank, sh, sp, sf);
        if (st == 0) /* lambda* = 0 by the positive-part rule */
            assert_true(lam == 0.0 && isfinite(b[0]) && isfinite(sp[0]));
        else {
            assert_int_equal(st, IGEA_EOVERFLOW);
            assert_true(all_sentinel(b, N) && all_sentinel(sp, N) &&
                        lam == SENTINEL && rank == -7);
        }
    }
    for (int i = 0; i < M * N; i++)
        As[i] = A[i] * 0x1p-60;
    double b[N], lam, sp[N], sf[N];
    int rank;
    assert_int_equal(ebr_old(M, N, As, M, y, NULL, IGEA_REGRESS_EBR_MM, 0.0, b,
                                      &lam, &rank, NULL, sp, sf), 0);
    assert_close(lam, l0 * 0x1p120, 1e-9);
    for (int j = 0; j < N; j++) {
        assert_close(b[j], b0[j] * 0x1p60, 1e-9);
        assert_close(sp[j], sp0[j] * 0x1p60, 1e-9);
        assert_close(sf[j], sf0[j] * 0x1p60, 1e-9);
    }
}

static void test_sigma_range(void **state)
{
    (void)state;
    /* A denormal sigma (1/sigma^2 = Inf) and one just below 2^-511: the
     * status names the range, outputs are untouched. 2^-511 is accepted. */
    const double bad[2] = {4e-320, 1e-160};
    for (int t = 0; t < 2; t++) {
        double sg[6] = {1, 1, 1, 1, 1, 1}, x[2], cov[4], res[6], s2 = SENTINEL,
               ku = SENTINEL;
        int rank = -7, nu = -7;
        sg[3] = bad[t];
        fill_sentinel(x, 2);
        fill_sentinel(cov, 4);
        fill_sentinel(res, 6);
        assert_int_equal(igea_regress_ls(6, 2, small_A, 6, small_y, sg, NULL, 0, x, cov,
                                         2, &rank, &s2, res), IGEA_ERANGE);
        assert_int_equal(igea_regress_ridge(6, 2, small_A, 6, small_y, sg, NULL,
                                            IGEA_REGRESS_RIDGE_GCV, 0, x, cov, 2, &ku,
                                            &s2, res), IGEA_ERANGE);
        assert_int_equal(igea_regress_pce(6, 2, small_A, 6, small_y, sg, NULL, 2, 0, x,
                                          cov, 2, &nu, &s2, res), IGEA_ERANGE);
        double P[4] = {1, 0, 0, 1}, kg[1] = {1.0}, cs[2], eig[2];
        assert_int_equal(igea_regress_bayes(6, 2, small_A, 6, small_y, sg, NULL, NULL,
                                            P, 2, x, cov, 2, res), IGEA_ERANGE);
        assert_int_equal(igea_regress_ridge_trace(6, 2, small_A, 6, small_y, sg, NULL,
                                                  1, kg, x, 2, NULL),
                         IGEA_ERANGE);
        fill_sentinel(cs, 2);
        assert_int_equal(igea_regress_collinearity(6, 2, small_A, 6, small_y, sg, NULL,
                                                   0, cs, &rank, eig, NULL, 2,
                                                   NULL, NULL, NULL),
                         IGEA_ERANGE);
        assert_true(all_sentinel(x, 2) && all_sentinel(cov, 4) &&
                    all_sentinel(res, 6) && all_sentinel(cs, 2) &&
                    s2 == SENTINEL && ku == SENTINEL && rank == -7 && nu == -7);
        /* EBR's prior scales are checked alike. */
        double ps[2] = {1.0, bad[t]}, lam = SENTINEL;
        assert_int_equal(ebr_old(6, 2, small_A, 6, small_y, ps,
                                          IGEA_REGRESS_EBR_MM, 0, x, &lam, &rank, NULL,
                                          NULL, NULL), IGEA_ERANGE);
        assert_true(lam == SENTINEL && all_sentinel(x, 2));
    }
    double sg[6] = {1, 1, 1, IGEA_SIGMA_MIN, 1, 1}, x[2], s2;
    int rank;
    assert_true(IGEA_SIGMA_MIN == 0x1p-511);
    assert_int_equal(igea_regress_ls(6, 2, small_A, 6, small_y, sg, NULL, 0, x, NULL,
                                     2, &rank, &s2, NULL), 0);
    assert_true(isfinite(x[0]) && isfinite(x[1]) && isfinite(s2));
    assert_true(strstr(igea_strerror(IGEA_ERANGE), "1.5e-154") != NULL);
}

/* spec_sigma: every estimator on A with column scales D equals the same
 * estimator on the design A D written out here, taken back by hand
 * (x = D x', cov = D cov' D); the Bayesian prior is taken to X / spec. EBR
 * with row sigmas equals EBR on the rows whitened here. */
enum { SM = 14, SN = 4 };
static void spec_problem(double *A, double *AD, double *y, double *sg, double *sp)
{
    static const double spec[SN] = {1.0, 2.5, 0.25, 4.0};
    for (int i = 0; i < SM; i++) {
        double t = 0.37 * (i + 1);
        sg[i] = 0.5 + 0.05 * i;
        y[i] = sin(t) + 0.1 * cos(3.1 * t);
        for (int j = 0; j < SN; j++) {
            A[i + SM * j] = cos(t * (j + 1)) + 0.2 * j;
            AD[i + SM * j] = A[i + SM * j] * spec[j];
        }
    }
    memcpy(sp, spec, sizeof spec);
}

static void check_unscaled(const double *sp, const double *x, const double *xr,
                           const double *cov, const double *cr)
{
    for (int j = 0; j < SN; j++) {
        assert_close_abs(x[j], sp[j] * xr[j], 1e-13, 1e-15);
        for (int i = 0; cov && i < SN; i++)
            assert_close_abs(cov[i + SN * j], sp[i] * cr[i + SN * j] * sp[j], 1e-13, 1e-17);
    }
}

static void test_spec_sigma_all_estimators(void **state)
{
    double A[SM * SN], AD[SM * SN], y[SM], sg[SM], sp[SN];
    double x[SN], xr[SN], cov[SN * SN], cr[SN * SN], res[SM], rr[SM], s2, s2r, q, qr;
    int rk, rkr;
    spec_problem(A, AD, y, sg, sp);
    assert_int_equal(igea_regress_ls(SM, SN, A, SM, y, sg, sp, 0.0, x, cov, SN, &rk, &s2, res), 0);
    assert_int_equal(igea_regress_ls(SM, SN, AD, SM, y, sg, NULL, 0.0, xr, cr, SN, &rkr, &s2r, rr), 0);
    check_unscaled(sp, x, xr, cov, cr);
    assert_int_equal(rk, rkr);
    assert_close(s2, s2r, 1e-13);
    for (int i = 0; i < SM; i++)
        assert_close_abs(res[i], rr[i], 1e-12, 1e-14);
    assert_int_equal(igea_regress_ridge(SM, SN, A, SM, y, sg, sp, IGEA_REGRESS_RIDGE_GCV, 0.0, x,
                                        cov, SN, &q, &s2, NULL), 0);
    assert_int_equal(igea_regress_ridge(SM, SN, AD, SM, y, sg, NULL, IGEA_REGRESS_RIDGE_GCV, 0.0,
                                        xr, cr, SN, &qr, &s2r, NULL), 0);
    check_unscaled(sp, x, xr, cov, cr);
    assert_close(q, qr, 1e-13);
    double k3[3] = {0.0, 0.3, 3.0}, X[SN * 3], Xr[SN * 3], e[3], er[3];
    assert_int_equal(igea_regress_ridge_trace(SM, SN, A, SM, y, sg, sp, 3, k3, X, SN, e), 0);
    assert_int_equal(igea_regress_ridge_trace(SM, SN, AD, SM, y, sg, NULL, 3, k3, Xr, SN, er), 0);
    for (int j = 0; j < 3; j++) {
        check_unscaled(sp, X + SN * j, Xr + SN * j, NULL, NULL);
        assert_close(e[j], er[j], 1e-13);
    }
    int nu, nur;
    assert_int_equal(igea_regress_pce(SM, SN, A, SM, y, sg, sp, 2, 0.0, x, cov, SN, &nu, &s2,
                                      NULL), 0);
    assert_int_equal(igea_regress_pce(SM, SN, AD, SM, y, sg, NULL, 2, 0.0, xr, cr, SN, &nur,
                                      &s2r, NULL), 0);
    check_unscaled(sp, x, xr, cov, cr);
    assert_int_equal(nu, 2);
    /* Bayes: prior mean mu, covariance P in the caller's units */
    double mu[SN] = {0.1, -0.4, 0.02, 1.0}, P[SN * SN] = {0}, mus[SN], Ps[SN * SN];
    for (int i = 0; i < SN; i++)
        for (int j = 0; j < SN; j++) {
            P[i + SN * j] = (i == j ? 1.0 : 0.3) * sp[i] * sp[j];
            Ps[i + SN * j] = i == j ? 1.0 : 0.3;
        }
    for (int i = 0; i < SN; i++)
        mus[i] = mu[i] / sp[i];
    assert_int_equal(igea_regress_bayes(SM, SN, A, SM, y, sg, sp, mu, P, SN, x, cov, SN, NULL), 0);
    assert_int_equal(igea_regress_bayes(SM, SN, AD, SM, y, sg, NULL, mus, Ps, SN, xr, cr, SN,
                                        NULL), 0);
    check_unscaled(sp, x, xr, cov, cr);
    /* no prior covariance: diag(spec^2), the identity on X / spec */
    double I4[SN * SN] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    assert_int_equal(igea_regress_bayes(SM, SN, A, SM, y, sg, sp, NULL, NULL, 0, x, cov, SN,
                                        NULL), 0);
    assert_int_equal(igea_regress_bayes(SM, SN, AD, SM, y, sg, NULL, NULL, I4, SN, xr, cr, SN,
                                        NULL), 0);
    check_unscaled(sp, x, xr, cov, cr);
    /* collinearity of A D */
    double cd[2], cdr[2], ev[SN], evr[SN], vf[SN], vfr[SN];
    assert_int_equal(igea_regress_collinearity(SM, SN, A, SM, y, sg, sp, 0.0, cd, &rk, ev, NULL,
                                               1, vf, NULL, NULL), 0);
    assert_int_equal(igea_regress_collinearity(SM, SN, AD, SM, y, sg, NULL, 0.0, cdr, &rkr, evr,
                                               NULL, 1, vfr, NULL, NULL), 0);
    assert_close(cd[0], cdr[0], 1e-13);
    for (int i = 0; i < SN; i++) {
        assert_close(ev[i], evr[i], 1e-13);
        assert_close(vf[i], vfr[i], 1e-12);
    }
}

static void test_ebr_sigma_and_cov(void **state)
{
    /* the 20 x 9 dual design: rows whitened by hand give the same EBR */
    double A[20 * 9], y[20], Aw[20 * 9], yw[20], sg[20], ds[9];
    ebr_data(3e-5, 20, A, y);
    for (int i = 0; i < 20; i++) {
        sg[i] = 0.5 + 0.1 * (i % 7);
        yw[i] = y[i] / sg[i];
        for (int j = 0; j < 9; j++)
            Aw[i + 20 * j] = A[i + 20 * j] / sg[i];
    }
    for (int j = 0; j < 9; j++)
        ds[j] = 1.0 + 0.5 * j;
    double b[9], br[9], cov[81], cr[81], lam, lr, s2, s2r, sh[9], shr[9], sf[9], sfr[9];
    double res[20];
    int r, rr;
    assert_int_equal(igea_regress_ebr(20, 9, A, 20, y, sg, ds, IGEA_REGRESS_EBR_SC, 0.0, b, cov,
                                      9, &lam, &r, &s2, res, sh, sf), 0);
    assert_int_equal(igea_regress_ebr(20, 9, Aw, 20, yw, NULL, ds, IGEA_REGRESS_EBR_SC, 0.0, br,
                                      cr, 9, &lr, &rr, &s2r, NULL, shr, sfr), 0);
    assert_int_equal(r, 7);
    assert_int_equal(rr, 7);
    assert_close(lam, lr, 1e-12);
    assert_close(s2, s2r, 1e-12);
    for (int j = 0; j < 9; j++) {
        assert_close_abs(b[j], br[j], 1e-12, 1e-18);
        assert_close(sf[j], sfr[j], 1e-12);
        assert_close_abs(sh[j], shr[j], 1e-12, 1e-15);
        for (int i = 0; i < 9; i++)
            assert_close_abs(cov[i + 9 * j], cr[i + 9 * j], 1e-11, 1e-24);
    }
    /* sigma^2 = S / (m - r), S the weighted RSS of least squares (rank 7) */
    double xl[9], s2l;
    int rl;
    assert_int_equal(igea_regress_ls(20, 9, A, 20, y, sg, NULL, 0.0, xl, NULL, 9, &rl, &s2l,
                                     NULL), 0);
    assert_int_equal(rl, 7);
    assert_close(s2, s2l, 1e-9);
    /* residual = y - A beta */
    for (int i = 0; i < 20; i++) {
        double e = y[i];
        for (int j = 0; j < 9; j++)
            e -= A[i + 20 * j] * b[j];
        assert_close_abs(res[i], e, 1e-9, 1e-15);
    }
    /* the posterior covariance is symmetric and its diagonal positive */
    for (int i = 0; i < 9; i++) {
        assert_true(cov[i * 10] > 0.0);
        for (int j = 0; j < 9; j++)
            assert_true(cov[i + 9 * j] == cov[j + 9 * i]);
    }
}

/* The shared kernels of src/linalg.c against closed forms. */
static void test_linalg_kernels(void **state)
{
    /* A = [3 0; 0 -4; 0 0] (3 x 2): s = (4, 3), v_1 = e_2 (sign +), u_1 =
     * -e_2 (flipped with v_1: A v_1 = (0, -4, 0) = 4 u_1), v_2 = e_1,
     * u_2 = e_1 */
    double a[6] = {3, 0, 0, 0, -4, 0}, s[2], U[9], V[4];
    assert_int_equal(igea__svd(3, 2, a, s, U, 0, V), 0);
    assert_close(s[0], 4.0, 1e-15);
    assert_close(s[1], 3.0, 1e-15);
    assert_close_abs(V[1], 1.0, 1e-15, 0);
    assert_close_abs(V[0], 0.0, 0, 1e-15);
    assert_close_abs(V[2], 1.0, 1e-15, 0);
    assert_close_abs(U[1], -1.0, 1e-15, 0);
    assert_close_abs(U[3], 1.0, 1e-15, 0);
    /* full U: the third column spans the left null space e_3 (+-) */
    double a2[6] = {3, 0, 0, 0, -4, 0};
    assert_int_equal(igea__svd(3, 2, a2, s, U, 1, V), 0);
    assert_close_abs(fabs(U[8]), 1.0, 1e-15, 0);
    /* wide: 1 x 3 [1 2 2]: s = 3, v_1 = (1, 2, 2)/3, V orthonormal */
    double w[3] = {1, 2, 2}, sw[1], Uw[1], Vw[9];
    assert_int_equal(igea__svd(1, 3, w, sw, Uw, 0, Vw), 0);
    assert_close(sw[0], 3.0, 1e-15);
    for (int i = 0; i < 3; i++)
        assert_close(Vw[i], (i == 0 ? 1.0 : 2.0) / 3.0, 1e-15);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = 0;
            for (int k = 0; k < 3; k++)
                d += Vw[k + 3 * i] * Vw[k + 3 * j];
            assert_close_abs(d, i == j ? 1.0 : 0.0, 1e-15, 1e-15);
        }
    /* rank cut: s_i > tol s_1 */
    const double sv[4] = {10, 1, 1e-9, 0};
    assert_int_equal(igea__rank_cut(4, sv, 1e-8), 2);
    assert_int_equal(igea__rank_cut(4, sv, 1e-10), 2); /* not above the cut */
    assert_int_equal(igea__rank_cut(4, sv, 1e-11), 3);
    const double z[2] = {0, 0};
    assert_int_equal(igea__rank_cut(2, z, 1e-8), 0);
    /* transpose */
    double t[4] = {1, 2, 3, 4};
    igea__transpose(2, t, 2);
    assert_true(t[0] == 1 && t[1] == 3 && t[2] == 2 && t[3] == 4);
    /* Cholesky of [4 2; 2 5] (+ shift 0): L = [2 0; 1 2]; of [0 0; 0 0] + I */
    double c[4] = {4, 2, -99, 5};
    assert_int_equal(igea__chol_lower(2, c, 2, 0.0), 0);
    assert_true(c[0] == 2 && c[1] == 1 && c[3] == 2 && c[2] == -99);
    double c1[4] = {0, 0, 0, 0};
    assert_int_equal(igea__chol_lower(2, c1, 2, 1.0), 0);
    assert_true(c1[0] == 1 && c1[1] == 0 && c1[3] == 1);
    double c2[4] = {1, 2, 0, 1}; /* [1 2; 2 1]: indefinite */
    assert_int_equal(igea__chol_lower(2, c2, 2, 0.0), IGEA_ESINGULAR);
    double c3[4] = {1, 0, 0, NAN};
    assert_int_equal(igea__chol_lower(2, c3, 2, 0.0), IGEA_ENONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ls_longley),
        cmocka_unit_test(test_ls_filip),
        cmocka_unit_test(test_ls_strd),
        cmocka_unit_test(test_ls_filip_exact),
        cmocka_unit_test(test_ls_strd_weighted),
        cmocka_unit_test(test_regress_sd),
        cmocka_unit_test(test_ridge_pce_autoscale),
        cmocka_unit_test(test_ls_diag_strd),
        cmocka_unit_test(test_rank_info),
        cmocka_unit_test(test_ls_weighted_line),
        cmocka_unit_test(test_ls_rank_deficient),
        cmocka_unit_test(test_ls_errors),
        cmocka_unit_test(test_ebr_vector),
        cmocka_unit_test(test_ebr_closed_forms),
        cmocka_unit_test(test_ebr_orthogonal),
        cmocka_unit_test(test_ebr_prior_scale),
        cmocka_unit_test(test_ebr_errors),
        cmocka_unit_test(test_ridge),
        cmocka_unit_test(test_ridge_published_longley),
        cmocka_unit_test(test_ridge_errors),
        cmocka_unit_test(test_pce),
        cmocka_unit_test(test_bayes),
        cmocka_unit_test(test_collinearity),
        cmocka_unit_test(test_wide_ls_pce_ridge),
        cmocka_unit_test(test_wide_1x3),
        cmocka_unit_test(test_wide_bayes_ebr_collinearity),
        cmocka_unit_test(test_scaled_designs),
        cmocka_unit_test(test_scaled_column_ridge),
        cmocka_unit_test(test_ebr_scaled),
        cmocka_unit_test(test_sigma_range),
        cmocka_unit_test(test_spec_sigma_all_estimators),
        cmocka_unit_test(test_ebr_sigma_and_cov),
        cmocka_unit_test(test_linalg_kernels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
