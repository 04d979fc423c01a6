/* stability_pass.c - one pass over a record for every averaging time of the
 * Allan and Hadamard families: the phase is built block by block from the
 * stream (rate samples integrated, or phase points as they come), kept in a
 * ring of the blocks that the longest lag still needs, each block as a base
 * (double-double) and values relative to it, and every requested tau takes
 * its terms from the block as it is closed (docs/stability.md, "One pass"). */
#include "igea/stability.h"
#include "internal.h"
#include "stability_internal.h"

#define AP_B IGEA__AP_BLOCK /* phase points per block */

/* ---- double-double ---- */

typedef igea__apdd dd;

static inline dd two_sum(double a, double b)
{
    double s = a + b, bb = s - a;
    dd r = {s, (a - (s - bb)) + (b - bb)};
    return r;
}

static inline dd fast_two_sum(double a, double b)
{
    double s = a + b;
    dd r = {s, b - (s - a)};
    return r;
}

static inline dd dd_add(dd a, dd b)
{
    dd s = two_sum(a.hi, b.hi);
    return fast_two_sum(s.hi, s.lo + a.lo + b.lo);
}

static inline dd dd_neg(dd a)
{
    dd r = {-a.hi, -a.lo};
    return r;
}

static inline dd dd_add_d(dd a, double b)
{
    dd s = two_sum(a.hi, b);
    return fast_two_sum(s.hi, s.lo + a.lo);
}

/* Dekker's exact product (no fused multiply-add needed). */
static inline dd two_prod(double a, double b)
{
    const double sp = 134217729.0; /* 2^27 + 1 */
    double p = a * b, ca = sp * a, cb = sp * b;
    double ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
    dd r = {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
    return r;
}

/* a times the small integer (or exact double) b. */
static inline dd dd_mul_d(dd a, double b)
{
    dd p = two_prod(a.hi, b);
    return fast_two_sum(p.hi, p.lo + a.lo * b);
}

static inline double dd_get(dd a) { return a.hi + a.lo; }

/* ---- lag-1 autocorrelation accumulators (rate kinds' noise type) ---- */

/* Sums of one series v_k less its first value sh: count, sum, sum of
 * squares, sum of v_k v_{k+1}, first and last (shifted), previous value;
 * the K new values of v appended (eight lanes combined in a fixed order). */
static void acf_block(igea__apacf *a, const double *v, long K)
{
    if (K <= 0)
        return;
    double s0 = 0, q0 = 0, g0 = 0;
    if (a->n == 0) {
        a->sh = v[0];
        a->first = 0.0;
    } else {
        double w = v[0] - a->sh;
        s0 = w;
        q0 = w * w;
        g0 = a->prev * w;
    }
    const double sh = a->sh;
    double s1 = 0, s2 = 0, s3 = 0, q1 = 0, q2 = 0, q3 = 0, g1 = 0, g2 = 0, g3 = 0;
    long i = 1;
    for (; i + 4 <= K; i += 4) {
        double u0 = v[i - 1] - sh, w0 = v[i] - sh, w1 = v[i + 1] - sh, w2 = v[i + 2] - sh,
               w3 = v[i + 3] - sh;
        s0 += w0;
        s1 += w1;
        s2 += w2;
        s3 += w3;
        q0 += w0 * w0;
        q1 += w1 * w1;
        q2 += w2 * w2;
        q3 += w3 * w3;
        g0 += u0 * w0;
        g1 += w0 * w1;
        g2 += w1 * w2;
        g3 += w2 * w3;
    }
    for (; i < K; i++) {
        double w = v[i] - sh, u = v[i - 1] - sh;
        s0 += w;
        q0 += w * w;
        g0 += u * w;
    }
    igea__ksum_add(&a->s, (s0 + s1) + (s2 + s3));
    igea__ksum_add(&a->ss, (q0 + q1) + (q2 + q3));
    igea__ksum_add(&a->lag, (g0 + g1) + (g2 + g3));
    a->n += (double)K;
    a->prev = a->last = v[K - 1] - sh;
}

/* ---- the pass ---- */

typedef struct {
    long m, span;  /* averaging factor; lag of the oldest point */
    int type;      /* IGEA__AP_AV, _HV, _MV */
    int stride;    /* 1 (overlapping) or 0 (stride m) */
    int acf;       /* lag-1 autocorrelation of the m-sample means */
    igea__ksum sum;
    long cnt;
    long nmean;    /* means pushed to the sums */
    double zc[3];  /* the last three means pushed */
    double *zb;    /* means waiting: zb[3 ..], zb[0 .. 2] the three before */
    long nzb, next_e; /* means waiting; the last point of the next mean */
    igea__ksum lag2;  /* sum of w_j w_{j+2} of the first differences (shifted) */
    double dfirst[2], dlast[2]; /* the first two and the last two differences */
    igea__apacf a[3];
} aptau;

struct igea__apass {
    int phase, need_l, need_v;
    long cap;          /* ring capacity, blocks */
    long cap_max;      /* blocks the longest lag can need */
    double *L, *V;     /* cap blocks of AP_B (L) and AP_B + 1 (V) values */
    dd *Xb, *Wb;       /* block bases of the phase and of its running sum */
    long k, fill;      /* current block, its points */
    long kbase;        /* the block in slot 0 of the current pass through the ring */
    double llast, vlast; /* the finished block's last L and V */
    double *lbuf;      /* the block's local values when L is not kept */
    long N;            /* phase points so far */
    double off;        /* rate feed: the offset removed (mean of the first block) */
    double *pend;      /* rate feed: the first block's samples until its mean is known */
    long npend;
    int started, ended;
    int bad;           /* a value was NaN or infinite */
    int ntau;
    aptau *t;
    double *z;         /* scratch: AP_B + 3 values */
};

/* The ring slot of block blk (blk in k - cap + 1 .. k): no division. */
static inline long slot_of(const igea__apass *p, long blk)
{
    long d = blk - p->kbase;
    return d < 0 ? d + p->cap : d;
}

/* X at phase index i as base slot and local value. */
static inline double *lptr(const igea__apass *p, long i)
{
    long b = i / AP_B;
    return p->L + (size_t)slot_of(p, b) * AP_B + (size_t)(i - b * AP_B);
}

static inline double *vptr(const igea__apass *p, long i)
{
    long b = i / AP_B;
    return p->V + (size_t)slot_of(p, b) * (AP_B + 1) + (size_t)(i - b * AP_B);
}

void igea__apass_free(igea__apass *p)
{
    if (!p)
        return;
    free(p->L);
    free(p->V);
    free(p->Xb);
    free(p->Wb);
    free(p->pend);
    for (int j = 0; p->t && j < p->ntau; j++)
        free(p->t[j].zb);
    free(p->t);
    free(p->z);
    free(p->lbuf);
    free(p);
}

/* realloc of n items of size sz (NULL on overflow or failure, p kept). */
static void *grow_array(void *p, size_t n, size_t sz)
{
    return n > (size_t)-1 / sz ? NULL : realloc(p, n * sz);
}

/* Grow the ring to newcap blocks, keeping blocks k - cap + 1 .. k. Before
 * the ring has wrapped (block k in slot k) the arrays are extended in
 * place (large ones by remapping, without a second copy). */
static int ring_grow(igea__apass *p, long newcap)
{
    if (p->cap > 0 && p->k < p->cap && p->kbase == 0) {
        dd *Xb = grow_array(p->Xb, (size_t)newcap, sizeof(dd));
        if (Xb)
            p->Xb = Xb;
        dd *Wb = Xb ? grow_array(p->Wb, (size_t)newcap, sizeof(dd)) : NULL;
        if (Wb)
            p->Wb = Wb;
        double *L = NULL, *V = NULL;
        if (Wb && p->need_l && (L = grow_array(p->L, (size_t)newcap * AP_B, sizeof(double))))
            p->L = L;
        if (Wb && p->need_v &&
            (V = grow_array(p->V, (size_t)newcap * (AP_B + 1), sizeof(double))))
            p->V = V;
        if (!Xb || !Wb || (p->need_l && !L) || (p->need_v && !V))
            return IGEA_ENOMEM; /* the arrays kept their old size and content */
        p->cap = newcap;
        return 0;
    }
    double *L = NULL, *V = NULL;
    dd *Xb = malloc((size_t)newcap * sizeof(dd)), *Wb = malloc((size_t)newcap * sizeof(dd));
    if (p->need_l)
        L = igea__dalloc((size_t)newcap * AP_B);
    if (p->need_v)
        V = igea__dalloc((size_t)newcap * (AP_B + 1));
    if (!Xb || !Wb || (p->need_l && !L) || (p->need_v && !V)) {
        free(Xb);
        free(Wb);
        free(L);
        free(V);
        return IGEA_ENOMEM;
    }
    long first = p->k - p->cap + 1;
    if (first < 0)
        first = 0;
    for (long b = first; b <= p->k && p->cap > 0; b++) {
        long so = b % p->cap, sn = b % newcap;
        Xb[sn] = p->Xb[so];
        Wb[sn] = p->Wb[so];
        if (L)
            memcpy(L + (size_t)sn * AP_B, p->L + (size_t)so * AP_B, AP_B * sizeof(double));
        if (V)
            memcpy(V + (size_t)sn * (AP_B + 1), p->V + (size_t)so * (AP_B + 1),
                   (AP_B + 1) * sizeof(double));
    }
    free(p->L);
    free(p->V);
    free(p->Xb);
    free(p->Wb);
    p->L = L;
    p->V = V;
    p->Xb = Xb;
    p->Wb = Wb;
    p->cap = newcap;
    p->kbase = p->k - p->k % newcap;
    return 0;
}

int igea__apass_new(int phase, int ntau, const igea__aptau_spec *spec, long nhint,
                    igea__apass **out)
{
    igea__apass *p = calloc(1, sizeof *p);
    if (!p)
        return IGEA_ENOMEM;
    p->phase = phase;
    p->ntau = ntau;
    p->t = calloc((size_t)(ntau > 0 ? ntau : 1), sizeof(aptau));
    p->z = igea__dalloc(AP_B + 3);
    p->lbuf = igea__dalloc(AP_B);
    p->pend = phase ? NULL : igea__dalloc(AP_B);
    if (!p->t || !p->z || !p->lbuf || (!phase && !p->pend)) {
        igea__apass_free(p);
        return IGEA_ENOMEM;
    }
    long span = 1;
    for (int j = 0; j < ntau; j++) {
        aptau *t = &p->t[j];
        t->m = spec[j].m;
        t->type = spec[j].type;
        t->stride = spec[j].stride;
        t->acf = spec[j].acf;
        t->span = (t->type == IGEA__AP_AV ? 2 : 3) * t->m;
        if (t->acf) { /* the three means before, 255 waiting, a block's */
            t->next_e = t->m;
            if (!(t->zb = igea__dalloc(3 + 255 + AP_B / (size_t)t->m + 1))) {
                igea__apass_free(p);
                return IGEA_ENOMEM;
            }
        }
        if (t->span > span)
            span = t->span;
        if (t->type == IGEA__AP_MV)
            p->need_v = 1;
        else
            p->need_l = 1;
        if (t->acf)
            p->need_l = p->need_l || !p->need_v;
    }
    if (!p->need_l && !p->need_v)
        p->need_l = 1;
    /* blocks the longest lag reaches back, plus the current one */
    p->cap_max = span / AP_B + 3;
    long c0 = p->cap_max;
    if (nhint > 0 && nhint / AP_B + 2 < c0)
        c0 = nhint / AP_B + 2;
    if (nhint <= 0 && c0 > 16)
        c0 = 16;
    if (ring_grow(p, c0)) {
        igea__apass_free(p);
        return IGEA_ENOMEM;
    }
    *out = p;
    return 0;
}

/* ---- the terms of one block ---- */

/* The segment kernels: eight accumulators (one per lane, combined in a
 * fixed order), so that a wider vector unit gives the same sums. Built
 * for AVX2 beside the baseline where the compiler can choose at load time
 * (GCC's target_clones; the results do not depend on the clone: no
 * contraction into fused multiply-adds under ISO C, the same lanes). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(IGEA_NO_CLONES)
#define AP_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define AP_CLONES
#endif

#if defined(__GNUC__)
/* Four doubles (GCC's vector extension; unaligned loads). */
typedef double ap_v4 __attribute__((vector_size(32), aligned(8)));
#define AP_LD(p) (*(const ap_v4 *)(const void *)(p))
#define AP_VEC 1
#else
#define AP_VEC 0
#endif

/* Sum of squares of EXPR(l) over the len values: eight lanes (element i + l
 * in lane l), the tail in lane 0, combined as ((0+1)+(2+3))+((4+5)+(6+7)).
 * The vector form computes the same lanes. */
#define AP_LANES8(EXPR)                                                                   \
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0;              \
    long i = 0;                                                                           \
    for (; i + 8 <= len; i += 8) {                                                        \
        double t0 = EXPR(0), t1 = EXPR(1), t2 = EXPR(2), t3 = EXPR(3), t4 = EXPR(4),      \
               t5 = EXPR(5), t6 = EXPR(6), t7 = EXPR(7);                                  \
        s0 += t0 * t0;                                                                    \
        s1 += t1 * t1;                                                                    \
        s2 += t2 * t2;                                                                    \
        s3 += t3 * t3;                                                                    \
        s4 += t4 * t4;                                                                    \
        s5 += t5 * t5;                                                                    \
        s6 += t6 * t6;                                                                    \
        s7 += t7 * t7;                                                                    \
    }                                                                                     \
    for (; i < len; i++) {                                                                \
        double t0 = EXPR(0);                                                              \
        s0 += t0 * t0;                                                                    \
    }                                                                                     \
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))

#if AP_VEC
#define AP_VLANES8(VEXPR, EXPR)                                                           \
    ap_v4 va = {0, 0, 0, 0}, vb = {0, 0, 0, 0};                                           \
    long i = 0;                                                                           \
    for (; i + 8 <= len; i += 8) {                                                        \
        ap_v4 ta = VEXPR(0), tb = VEXPR(4);                                               \
        va += ta * ta;                                                                    \
        vb += tb * tb;                                                                    \
    }                                                                                     \
    double s0 = va[0], s1 = va[1], s2 = va[2], s3 = va[3], s4 = vb[0], s5 = vb[1],        \
           s6 = vb[2], s7 = vb[3];                                                        \
    for (; i < len; i++) {                                                                \
        double t0 = EXPR(0);                                                              \
        s0 += t0 * t0;                                                                    \
    }                                                                                     \
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))
#endif

/* Sum of squares of ((a0 - a1) - (a1 - a2)) + C over len values. */
AP_CLONES static double seg_av(const double *a0, const double *a1, const double *a2, long len,
                               double C)
{
#define AP_AV_T(l) (((a0[i + l] - a1[i + l]) - (a1[i + l] - a2[i + l])) + C)
#if AP_VEC
#define AP_AV_V(l)                                                                        \
    (((AP_LD(a0 + i + l) - AP_LD(a1 + i + l)) - (AP_LD(a1 + i + l) - AP_LD(a2 + i + l))) + C)
    AP_VLANES8(AP_AV_V, AP_AV_T);
#undef AP_AV_V
#else
    AP_LANES8(AP_AV_T);
#endif
#undef AP_AV_T
}

/* Third differences ((a0 - a1) - (a1 - a2)) - ((a1 - a2) - (a2 - a3)) + C. */
AP_CLONES static double seg_hv(const double *a0, const double *a1, const double *a2,
                               const double *a3, long len, double C)
{
#define AP_HV_T(l)                                                                        \
    (((((a0[i + l] - a1[i + l]) - (a1[i + l] - a2[i + l])) -                              \
       ((a1[i + l] - a2[i + l]) - (a2[i + l] - a3[i + l])))) + C)
#if AP_VEC
#define AP_HV_V(l)                                                                        \
    (((((AP_LD(a0 + i + l) - AP_LD(a1 + i + l)) - (AP_LD(a1 + i + l) - AP_LD(a2 + i + l))) - \
       ((AP_LD(a1 + i + l) - AP_LD(a2 + i + l)) - (AP_LD(a2 + i + l) - AP_LD(a3 + i + l))))) + \
     C)
    AP_VLANES8(AP_HV_V, AP_HV_T);
#undef AP_HV_V
#else
    AP_LANES8(AP_HV_T);
#endif
#undef AP_HV_T
}

/* Modified: ((v0 - v3) - 3 (v1 - v2)) + (A + i B) (the index i counted in
 * doubles). */
AP_CLONES static double seg_mv(const double *v0, const double *v1, const double *v2,
                               const double *v3, long len, double A, double Bc)
{
#define AP_MV_T(l)                                                                        \
    (((v0[i + l] - v3[i + l]) - 3.0 * (v1[i + l] - v2[i + l])) + (A + ((double)i + l) * Bc))
#if AP_VEC
    const ap_v4 lo = {0, 1, 2, 3}, hi = {4, 5, 6, 7};
#define AP_MV_V(l)                                                                        \
    (((AP_LD(v0 + i + l) - AP_LD(v3 + i + l)) -                                           \
      3.0 * (AP_LD(v1 + i + l) - AP_LD(v2 + i + l))) +                                    \
     (A + ((double)i + (l ? hi : lo)) * Bc))
    AP_VLANES8(AP_MV_V, AP_MV_T);
#undef AP_MV_V
#else
    AP_LANES8(AP_MV_T);
#endif
#undef AP_MV_T
}

/* The same with every point in one block (no linear part). */
AP_CLONES static double seg_mv0(const double *v0, const double *v1, const double *v2,
                                const double *v3, long len)
{
#define AP_MV0_T(l) ((v0[i + l] - v3[i + l]) - 3.0 * (v1[i + l] - v2[i + l]))
#if AP_VEC
#define AP_MV0_V(l)                                                                       \
    ((AP_LD(v0 + i + l) - AP_LD(v3 + i + l)) - 3.0 * (AP_LD(v1 + i + l) - AP_LD(v2 + i + l)))
    AP_VLANES8(AP_MV0_V, AP_MV0_T);
#undef AP_MV0_V
#else
    AP_LANES8(AP_MV0_T);
#endif
#undef AP_MV0_T
}

/* Sum over len values of ((a - b) + (c - e))^2 (Theo1's terms at one
 * offset), eight lanes as the other kernels. */
AP_CLONES static double seg_t1(const double *a, const double *b, const double *c,
                               const double *e, long len)
{
#define AP_T1_T(l) ((a[i + l] - b[i + l]) + (c[i + l] - e[i + l]))
#if AP_VEC
#define AP_T1_V(l) ((AP_LD(a + i + l) - AP_LD(b + i + l)) + (AP_LD(c + i + l) - AP_LD(e + i + l)))
    AP_VLANES8(AP_T1_V, AP_T1_T);
#undef AP_T1_V
#else
    AP_LANES8(AP_T1_T);
#endif
#undef AP_T1_T
}

/* (A cloned function with external linkage would be exported whatever its
 * visibility: the clones stay static.) */
double igea__ap_sumsq4(const double *a, const double *b, const double *c, const double *e,
                       long len)
{
    return seg_t1(a, b, c, e, len);
}

/* Coefficients of the difference at lags 0, m, 2m, 3m. */
static const double cAV[4] = {1, -2, 1, 0}, cHV[4] = {1, -3, 3, -1};

/* The overlapping terms of tau t with current index in [e0, e1). */
static void terms_overlap(igea__apass *p, aptau *t, long e0, long e1)
{
    int np = t->type == IGEA__AP_AV ? 3 : 4;
    double tot = 0.0;
    long e = e0;
    while (e < e1) {
        /* the segment where every lag stays in one block */
        long end = e1;
        for (int q = 1; q < np; q++) {
            long i = e - q * t->m, nb = (i / AP_B + 1) * AP_B; /* next block start */
            if (e + (nb - i) < end)
                end = e + (nb - i);
        }
        long len = end - e, b0 = e / AP_B;
        const double *a[4];
        long blk[4];
        int same = 1;
        for (int q = 0; q < np; q++) {
            long i = e - q * t->m;
            blk[q] = i / AP_B;
            a[q] = t->type == IGEA__AP_MV ? vptr(p, i) : lptr(p, i);
            same = same && blk[q] == b0;
        }
        if (t->type == IGEA__AP_MV) {
            double A = 0.0, Bc = 0.0;
            if (!same) {
                dd Ad = {0, 0}, Bd = {0, 0};
                for (int q = 0; q < 4; q++) {
                    long s = slot_of(p, blk[q]);
                    long off = e - q * t->m - blk[q] * AP_B;
                    dd w = dd_add(p->Wb[s], dd_mul_d(p->Xb[s], (double)off));
                    Ad = dd_add(Ad, dd_mul_d(w, cHV[q]));
                    Bd = dd_add(Bd, dd_mul_d(p->Xb[s], cHV[q]));
                }
                A = dd_get(Ad);
                Bc = dd_get(Bd);
            }
            tot += same ? seg_mv0(a[0], a[1], a[2], a[3], len)
                        : seg_mv(a[0], a[1], a[2], a[3], len, A, Bc);
        } else {
            double C = 0.0;
            if (!same) {
                dd Cd = {0, 0};
                const double *c = t->type == IGEA__AP_AV ? cAV : cHV;
                for (int q = 0; q < np; q++)
                    Cd = dd_add(Cd, dd_mul_d(p->Xb[slot_of(p, blk[q])], c[q]));
                C = dd_get(Cd);
            }
            tot += t->type == IGEA__AP_AV ? seg_av(a[0], a[1], a[2], len, C)
                                          : seg_hv(a[0], a[1], a[2], a[3], len, C);
        }
        e = end;
    }
    igea__ksum_add(&t->sum, tot);
    t->cnt += e1 - e0;
}

/* Strided segment: the terms at a0[j st], a1[j st], ... (scalar). */
static double seg_stride(const aptau *t, const double *const *a, long cnt, long st, double C)
{
    double s0 = 0, s1 = 0;
    for (long j = 0; j < cnt; j++) {
        const long o = j * st;
        double v;
        if (t->type == IGEA__AP_AV) {
            v = ((a[0][o] - a[1][o]) - (a[1][o] - a[2][o])) + C;
        } else {
            double u = a[1][o] - a[2][o];
            v = (((a[0][o] - a[1][o]) - u) - (u - (a[2][o] - a[3][o]))) + C;
        }
        if (j & 1)
            s1 += v * v;
        else
            s0 += v * v;
    }
    return s0 + s1;
}

/* The strided terms (current index a multiple of m) in [e0, e1) of one
 * block (the non-overlapping Allan and Hadamard kinds). */
static void terms_stride(igea__apass *p, aptau *t, long e0, long e1)
{
    if (t->m == 1) {
        terms_overlap(p, t, e0, e1);
        return;
    }
    int np = t->type == IGEA__AP_AV ? 3 : 4;
    long m = t->m, e = (e0 + m - 1) / m * m;
    double tot = 0.0;
    while (e < e1) {
        long end = e1, b0 = e / AP_B;
        for (int q = 1; q < np; q++) {
            long i = e - q * m, nb = (i / AP_B + 1) * AP_B;
            long steps = (nb - i + m - 1) / m;
            if (e + steps * m < end)
                end = e + steps * m;
        }
        long cnt = (end - e + m - 1) / m;
        const double *a[4];
        int same = 1;
        dd Cd = {0, 0};
        const double *c = t->type == IGEA__AP_AV ? cAV : cHV;
        for (int q = 0; q < np; q++) {
            long i = e - q * m, b = i / AP_B;
            a[q] = lptr(p, i);
            Cd = dd_add(Cd, dd_mul_d(p->Xb[slot_of(p, b)], c[q]));
            same = same && b == b0;
        }
        tot += seg_stride(t, a, cnt, m, same ? 0.0 : dd_get(Cd));
        t->cnt += cnt;
        e += cnt * m;
    }
    igea__ksum_add(&t->sum, tot);
}

/* z[j] = (X_e - X_{e - m}) / m for the points e = e0, e0 + m, ... < e1 of
 * one block (e0 a multiple of m): at most two segments where X_{e - m}
 * stays in one block. Returns their number. */
static long means_of(const igea__apass *p, long m, long e0, long e1, double *z)
{
    long K = 0, e = e0;
    int pow2 = (m & (m - 1)) == 0;
    double inv = 1.0 / (double)m;
    while (e < e1) {
        long i = e - m, bi = i / AP_B, be = e / AP_B;
        long nb = (bi + 1) * AP_B; /* lag leaves its block */
        long end = e1;
        long steps = (nb - i + m - 1) / m;
        if (e + steps * m < end)
            end = e + steps * m;
        double C = 0.0;
        if (bi != be)
            C = dd_get(dd_add(p->Xb[slot_of(p, be)], dd_neg(p->Xb[slot_of(p, bi)])));
        long cnt = (end - e + m - 1) / m;
        if (p->need_l) {
            const double *a0 = lptr(p, e), *a1 = lptr(p, i);
            if (m == 1)
                for (long j = 0; j < cnt; j++)
                    z[K + j] = (a0[j] - a1[j]) + C;
            else if (pow2)
                for (long j = 0; j < cnt; j++)
                    z[K + j] = ((a0[j * m] - a1[j * m]) + C) * inv;
            else
                for (long j = 0; j < cnt; j++)
                    z[K + j] = ((a0[j * m] - a1[j * m]) + C) / (double)m;
        } else { /* X_t = W_{t+1} - W_t within a block */
            const double *v0 = vptr(p, e), *v1 = vptr(p, i);
            for (long j = 0; j < cnt; j++)
                z[K + j] = (((v0[j * m + 1] - v0[j * m]) - (v1[j * m + 1] - v1[j * m])) + C) /
                           (double)m;
        }
        K += cnt;
        e += cnt * m;
    }
    return K;
}

/* Sums over i < K of the shifted means w0(i) = z(i) - sh0 and first
 * differences w1(i) = (z(i) - z(i-1)) - sh1: out = {sum w0, sum w0^2, sum
 * w0(i-1) w0(i), sum w1, sum w1^2, sum w1(i-1) w1(i), sum w1(i-2) w1(i)}
 * (the second differences' sums follow from the last two, docs). z[-3] ..
 * z[-1] hold the three means before z[0]. Four lanes in a fixed order. */
AP_CLONES static void acf_sums(const double *z, long K, double h0, double h1, double *out)
{
#define AP_ACF_DECL(l)                                                                    \
    double s0##l = 0, q0##l = 0, g0##l = 0, s1##l = 0, q1##l = 0, g1##l = 0, k1##l = 0
    AP_ACF_DECL(0);
    AP_ACF_DECL(1);
    AP_ACF_DECL(2);
    AP_ACF_DECL(3);
#define AP_ACF_LANE(l)                                                                    \
    {                                                                                     \
        double a = z[i + l], b = z[i + l - 1], c = z[i + l - 2], e = z[i + l - 3];        \
        double w0 = a - h0, u0 = b - h0;                                                  \
        double w1 = (a - b) - h1, u1 = (b - c) - h1, v1 = (c - e) - h1;                   \
        s0##l += w0;                                                                      \
        q0##l += w0 * w0;                                                                 \
        g0##l += u0 * w0;                                                                 \
        s1##l += w1;                                                                      \
        q1##l += w1 * w1;                                                                 \
        g1##l += u1 * w1;                                                                 \
        k1##l += v1 * w1;                                                                 \
    }
    long i = 0;
#if AP_VEC
    {
        ap_v4 S0 = {0, 0, 0, 0}, Q0 = S0, G0 = S0, S1 = S0, Q1 = S0, G1 = S0, K1 = S0;
        for (; i + 4 <= K; i += 4) {
            ap_v4 a = AP_LD(z + i), b = AP_LD(z + i - 1), c = AP_LD(z + i - 2),
                  e = AP_LD(z + i - 3);
            ap_v4 w0 = a - h0, u0 = b - h0;
            ap_v4 w1 = (a - b) - h1, u1 = (b - c) - h1, v1 = (c - e) - h1;
            S0 += w0;
            Q0 += w0 * w0;
            G0 += u0 * w0;
            S1 += w1;
            Q1 += w1 * w1;
            G1 += u1 * w1;
            K1 += v1 * w1;
        }
#define AP_ACF_GET(l)                                                                     \
    s0##l = S0[l], q0##l = Q0[l], g0##l = G0[l], s1##l = S1[l], q1##l = Q1[l],            \
    g1##l = G1[l], k1##l = K1[l]
        AP_ACF_GET(0);
        AP_ACF_GET(1);
        AP_ACF_GET(2);
        AP_ACF_GET(3);
#undef AP_ACF_GET
    }
#else
    for (; i + 4 <= K; i += 4) {
        AP_ACF_LANE(0)
        AP_ACF_LANE(1)
        AP_ACF_LANE(2)
        AP_ACF_LANE(3)
    }
#endif
    for (; i < K; i++)
        AP_ACF_LANE(0)
#define AP_ACF_SUM(v) ((v##0 + v##1) + (v##2 + v##3))
    out[0] = AP_ACF_SUM(s0), out[1] = AP_ACF_SUM(q0), out[2] = AP_ACF_SUM(g0);
    out[3] = AP_ACF_SUM(s1), out[4] = AP_ACF_SUM(q1), out[5] = AP_ACF_SUM(g1);
    out[6] = AP_ACF_SUM(k1);
#undef AP_ACF_DECL
#undef AP_ACF_LANE
#undef AP_ACF_SUM
}

/* The means waiting in t->zb to the sums of the series and of its first
 * differences. */
static void means_flush(aptau *t)
{
    double *zz = t->zb, *z = zz + 3;
    long K = t->nzb, i = 0;
    if (K == 0)
        return;
    zz[0] = t->zc[0];
    zz[1] = t->zc[1];
    zz[2] = t->zc[2];
    /* the first three means of the record start the series one by one */
    for (; i < K && t->nmean + i < 3; i++) {
        long g = t->nmean + i;
        acf_block(&t->a[0], z + i, 1);
        if (g >= 1) {
            double d = z[i] - z[i - 1];
            acf_block(&t->a[1], &d, 1);
            t->dfirst[g - 1] = d;
        }
    }
    if (i < K) {
        double o[7];
        acf_sums(z + i, K - i, t->a[0].sh, t->a[1].sh, o);
        for (int r = 0; r < 2; r++) {
            igea__apacf *a = &t->a[r];
            double zl = z[K - 1], z1 = z[K - 2];
            igea__ksum_add(&a->s, o[3 * r]);
            igea__ksum_add(&a->ss, o[3 * r + 1]);
            igea__ksum_add(&a->lag, o[3 * r + 2]);
            a->n += (double)(K - i);
            a->prev = a->last = (r == 0 ? zl : zl - z1) - a->sh;
        }
        igea__ksum_add(&t->lag2, o[6]);
    }
    if (t->nmean + K >= 3) {
        t->dlast[0] = z[K - 2] - z[K - 3];
        t->dlast[1] = z[K - 1] - z[K - 2];
    }
    t->nmean += K;
    t->zc[0] = z[K - 3];
    t->zc[1] = z[K - 2];
    t->zc[2] = z[K - 1];
    t->nzb = 0;
}

/* The m-sample means whose last point is in [.., e1) of the current block
 * wait in t->zb; 256 or more go to the sums. */
static void means_push(igea__apass *p, aptau *t, long e1)
{
    if (t->next_e >= e1)
        return;
    long K = means_of(p, t->m, t->next_e, e1, t->zb + 3 + t->nzb);
    t->nzb += K;
    t->next_e += K * t->m;
    if (t->nzb >= 256)
        means_flush(t);
}

/* The terms with current phase index in block k at offsets [x0, x1) and
 * current running-sum index (the modified kinds) at offsets [w0, w1). */
static void block_terms(igea__apass *p, long k, long x0, long x1, long w0, long w1)
{
    long base = k * AP_B;
    for (int j = 0; j < p->ntau; j++) {
        aptau *t = &p->t[j];
        int w = t->type == IGEA__AP_MV;
        long lo = base + (w ? w0 : x0), hi = base + (w ? w1 : x1);
        if (lo < t->span)
            lo = t->span;
        if (lo < hi) {
            if (t->stride)
                terms_overlap(p, t, lo, hi);
            else
                terms_stride(p, t, lo, hi);
        }
        if (t->acf)
            means_push(p, t, base + x1);
    }
}

/* Inclusive prefix sums out[j] = d[0] + ... + d[j], j < n <= AP_B (in place
 * allowed): eight lanes of AP_B / 8 values summed side by side, then each
 * lane offset by the totals of the lanes before it (values past n taken as
 * 0, so that a block's sums do not depend on how it was fed). */
static void prefix2(const double *d, double *out, long n)
{
    enum { W = AP_B / 8 };
    double a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0, a6 = 0, a7 = 0;
    if (n == AP_B) {
        for (long r = 0; r < W; r++) {
            a0 += d[r];
            a1 += d[W + r];
            a2 += d[2 * W + r];
            a3 += d[3 * W + r];
            a4 += d[4 * W + r];
            a5 += d[5 * W + r];
            a6 += d[6 * W + r];
            a7 += d[7 * W + r];
            out[r] = a0;
            out[W + r] = a1;
            out[2 * W + r] = a2;
            out[3 * W + r] = a3;
            out[4 * W + r] = a4;
            out[5 * W + r] = a5;
            out[6 * W + r] = a6;
            out[7 * W + r] = a7;
        }
    } else {
        double acc[8] = {0};
        for (long j = 0; j < n; j++) {
            acc[j / W] += d[j];
            out[j] = acc[j / W];
        }
        a0 = acc[0], a1 = acc[1], a2 = acc[2], a3 = acc[3], a4 = acc[4], a5 = acc[5];
        a6 = acc[6];
    }
    double off[8];
    off[0] = 0.0;
    off[1] = a0;
    off[2] = off[1] + a1;
    off[3] = off[2] + a2;
    off[4] = off[3] + a3;
    off[5] = off[4] + a4;
    off[6] = off[5] + a5;
    off[7] = off[6] + a6;
    for (int l = 1; l < 8; l++) {
        long r1 = n - l * W < W ? n - l * W : W;
        double o = off[l], *q = out + l * W;
        for (long r = 0; r < r1; r++)
            q[r] += o;
    }
}

/* The current block (fill points, raw values in the block's L slot or in
 * lbuf) becomes local values L (and V), then its terms are computed. */
static void block_finish(igea__apass *p, long x1, long w1)
{
    long k = p->k, s = slot_of(p, k), f = p->fill;
    double *L = p->need_l ? p->L + (size_t)s * AP_B : p->lbuf;
    if (p->phase) {
        double x0 = L[0], c0 = 0, c1 = 0, c2 = 0, c3 = 0;
        p->Xb[s].hi = x0;
        p->Xb[s].lo = 0.0;
        long j = 0;
        for (; j + 4 <= f; j += 4) {
            c0 += L[j] * 0.0;
            c1 += L[j + 1] * 0.0;
            c2 += L[j + 2] * 0.0;
            c3 += L[j + 3] * 0.0;
        }
        for (; j < f; j++)
            c0 += L[j] * 0.0;
        if (!((c0 + c1) + (c2 + c3) == 0.0))
            p->bad = 1;
        for (j = 0; j < f; j++)
            L[j] -= x0;
    } else {
        if (k > 0) { /* the base: the previous block's last point plus the sample */
            long ps = slot_of(p, k - 1);
            p->Xb[s] = dd_add_d(dd_add_d(p->Xb[ps], p->llast), L[0]);
        } else {
            p->Xb[s].hi = p->Xb[s].lo = 0.0;
        }
        L[0] = 0.0;
        prefix2(L, L, f);
        if (!(isfinite(L[f - 1]) && isfinite(p->Xb[s].hi)))
            p->bad = 1; /* a NaN or infinity spreads to the block's last sum */
    }
    p->llast = L[f - 1];
    if (p->need_v) {
        double *V = p->V + (size_t)s * (AP_B + 1);
        if (k > 0) {
            long ps = slot_of(p, k - 1);
            p->Wb[s] = dd_add_d(dd_add(p->Wb[ps], dd_mul_d(p->Xb[ps], (double)AP_B)), p->vlast);
        } else {
            p->Wb[s].hi = p->Wb[s].lo = 0.0;
        }
        V[0] = 0.0;
        prefix2(L, V + 1, f);
        p->vlast = V[f];
    }
    block_terms(p, k, 0, x1 < 0 ? f : x1, 0, w1 < 0 ? f : w1);
}

/* Room for the next block. */
static int block_next(igea__apass *p)
{
    if (p->k + 1 >= p->cap && p->cap < p->cap_max) {
        long nc = p->cap + p->cap / 2 + 1; /* 1.5 x: at most a third unused */
        if (nc > p->cap_max)
            nc = p->cap_max;
        if (ring_grow(p, nc))
            return IGEA_ENOMEM;
    }
    p->k++;
    if (p->k - p->kbase == p->cap)
        p->kbase += p->cap;
    p->fill = 0;
    return 0;
}

/* Raw values into the current block: rate samples (offset removed) or
 * phase points; a full block is finished. */
static int feed_raw(igea__apass *p, long n, const double *v)
{
    long i = 0;
    while (i < n) {
        if (p->fill == AP_B) {
            block_finish(p, -1, -1);
            if (block_next(p))
                return IGEA_ENOMEM;
        }
        double *L = p->need_l ? p->L + (size_t)slot_of(p, p->k) * AP_B : p->lbuf;
        long take = AP_B - p->fill;
        if (take > n - i)
            take = n - i;
        if (p->phase)
            memcpy(L + p->fill, v + i, (size_t)take * sizeof(double));
        else
            for (long j = 0; j < take; j++)
                L[p->fill + j] = v[i + j] - p->off;
        p->fill += take;
        p->N += take;
        i += take;
    }
    return 0;
}

/* The first block's samples are held until their mean (the offset) is known. */
static int rate_start(igea__apass *p)
{
    igea__ksum k = {0, 0};
    for (long i = 0; i < p->npend; i++)
        igea__ksum_add(&k, p->pend[i]);
    p->off = p->npend ? igea__ksum_get(&k) / (double)p->npend : 0.0;
    p->started = 1;
    p->fill = 1; /* X_0 = 0 */
    p->N = 1;
    return feed_raw(p, p->npend, p->pend);
}

int igea__apass_feed(igea__apass *p, long n, const double *v)
{
    if (p->ended)
        return -1;
    if (p->phase) {
        p->started = p->started || n > 0;
        return feed_raw(p, n, v);
    }
    long i = 0;
    while (!p->started && i < n) {
        p->pend[p->npend++] = v[i++];
        if (p->npend == AP_B) {
            int st = rate_start(p);
            if (st)
                return st;
        }
    }
    return i < n ? feed_raw(p, n - i, v + i) : 0;
}

static int apass_last(igea__apass *p);

int igea__apass_end(igea__apass *p)
{
    if (p->ended)
        return 0;
    if (!p->phase && !p->started) {
        int st = rate_start(p);
        if (st)
            return st;
    }
    p->ended = 1;
    if (!p->started || p->fill == 0)
        return 0;
    int st = apass_last(p);
    for (int j = 0; j < p->ntau; j++)
        if (p->t[j].acf)
            means_flush(&p->t[j]);
    return st;
}

/* The last block's terms. */
static int apass_last(igea__apass *p)
{
    /* the last block: X indices up to fill - 1, running sums up to fill
     * (W_N; when the block is full, the first of an empty next block) */
    long f = p->fill;
    if (f < AP_B || !p->need_v) {
        block_finish(p, f, f < AP_B ? f + 1 : f);
        return 0;
    }
    block_finish(p, AP_B, AP_B);
    if (block_next(p))
        return IGEA_ENOMEM;
    long s = slot_of(p, p->k), ps = slot_of(p, p->k - 1);
    p->Xb[s].hi = p->Xb[s].lo = 0.0;
    p->Wb[s] = dd_add_d(dd_add(p->Wb[ps], dd_mul_d(p->Xb[ps], (double)AP_B)), p->vlast);
    p->V[(size_t)s * (AP_B + 1)] = 0.0;
    block_terms(p, p->k, 0, 0, 0, 1);
    return 0;
}

long igea__apass_points(const igea__apass *p) { return p->N; }
int igea__apass_nonfinite(const igea__apass *p) { return p->bad; }
double igea__apass_offset(const igea__apass *p) { return p->off; }

void igea__apass_get(const igea__apass *p, int j, double *sumsq, long *count)
{
    *sumsq = igea__ksum_get(&p->t[j].sum);
    *count = p->t[j].cnt;
}

/* r1 of an accumulated series (Riley and Greenhall's estimator with the
 * series mean removed). */
static double apacf_r1(const igea__apacf *a)
{
    double N = a->n, s = igea__ksum_get(&a->s), zb = s / N;
    double den = igea__ksum_get(&a->ss) - N * zb * zb;
    double num = igea__ksum_get(&a->lag) - zb * (s - a->last) - zb * (s - a->first) +
                 (N - 1) * zb * zb;
    return den > 0.0 ? num / den : 0.0;
}

int igea__apass_alpha(const igea__apass *p, int j)
{
    const aptau *t = &p->t[j];
    if (!t->acf || t->nmean < 32)
        return IGEA_STABILITY_NOISE_AUTO;
    /* the second differences e_j = w_j - w_{j-1} of the K - 1 first
     * differences w_j (shifted, j = 1 .. K-1) from their sums D2 = sum w^2,
     * L1 = sum w_j w_{j+1}, L2 = sum w_j w_{j+2} and the end values
     * (docs/stability.md) */
    igea__apacf e = {0};
    {
        double sh = t->a[1].sh, K = (double)t->nmean;
        double w1 = t->dfirst[0] - sh, w2 = t->dfirst[1] - sh;
        double wk1 = t->dlast[0] - sh, wk = t->dlast[1] - sh;
        double D2 = igea__ksum_get(&t->a[1].ss), L1 = igea__ksum_get(&t->a[1].lag);
        double L2 = igea__ksum_get(&t->lag2);
        e.n = K - 2.0;
        igea__ksum_add(&e.s, wk - w1);
        igea__ksum_add(&e.ss, 2.0 * D2 - w1 * w1 - wk * wk - 2.0 * L1);
        igea__ksum_add(&e.lag, 2.0 * L1 - w1 * w2 - wk1 * wk - D2 + w1 * w1 + wk * wk - L2);
        e.first = w2 - w1;
        e.last = wk - wk1;
    }
    for (int d = 0; d <= 2; d++) {
        double r1 = apacf_r1(d == 2 ? &e : &t->a[d]), delta = r1 / (1.0 + r1);
        if (delta < 0.25 || d == 2) {
            long alpha = lround(-2.0 * (delta + d));
            return (int)IGEA_MAX(IGEA_STABILITY_NOISE_RWFM, IGEA_MIN(IGEA_STABILITY_NOISE_WPM, alpha));
        }
    }
    return IGEA_STABILITY_NOISE_WFM;
}
