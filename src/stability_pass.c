/* stability_pass.c - one pass over a record for every averaging time of the
 * Allan and Hadamard families. The phase is built block by block (rate
 * samples integrated, or phase points as they come), each block as a base
 * (double-double) and values relative to it. A tau whose lags reach no
 * further back than the small ring of the last AP_RS_MAX blocks takes its
 * terms from the local values kept there; a longer lag reads the raw values
 * of the record itself (a whole-record call: the caller's array; a stream:
 * a ring of raw values as long as that lag) and runs the differences as a
 * recurrence from exact anchors; the strided terms and the tau-means of
 * long lags keep the last points at multiples of m (docs/stability.md,
 * "One pass"). */
#include <stdint.h>

#include "igea/stability.h"
#include "internal.h"
#include "stability_internal.h"

#define AP_B IGEA__AP_BLOCK /* phase points per block */
#ifndef AP_RS_MAX
#define AP_RS_MAX 256 /* blocks of the small ring of local values (a build with
                       * -DAP_RS_MAX=2 sends nearly every lag down the long
                       * path: tests/test_stability.c then checks it on short
                       * records) */
#endif
#define AP_REANCHOR 4       /* lags off the block grid: exact anchors every 4 blocks */
#define AP_BUF (AP_B + 16)  /* one stream of the scratch buffer */
#define AP_VS (AP_B + 8)    /* a block of the ring of V (AP_B + 1 values from the 4th) */
#define AP_NLEV 16          /* levels of pyr_block: m = 1, 2, 4, ... < AP_B */
#ifndef AP_DEFER
#define AP_DEFER 64 /* blocks whose long-lag terms are taken together, tau by tau
                     * (a stream keeps as many more raw values) */
#endif

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

static inline dd dd_sub(dd a, dd b) { return dd_add(a, dd_neg(b)); }

/* v0 - 2 v1 + v2 as (v0 - v1) - (v1 - v2). */
static inline dd dd_diff2(const dd *v) { return dd_sub(dd_sub(v[0], v[1]), dd_sub(v[1], v[2])); }

/* v0 - 3 v1 + 3 v2 - v3 as (v0 - v3) - 3 (v1 - v2), 3 u = u + 2 u. */
static inline dd dd_diff3(const dd *v)
{
    dd u = dd_sub(v[1], v[2]), u2 = {2.0 * u.hi, 2.0 * u.lo};
    return dd_sub(dd_sub(v[0], v[3]), dd_add(u, u2));
}

/* ---- the pass ---- */

typedef struct {
    long m, span;  /* averaging factor; lag of the oldest point */
    int type;      /* IGEA__AP_AV, _HV, _MV */
    int stride;    /* 1 (overlapping) or 0 (stride m) */
    int acf;       /* lag-1 autocorrelation of the m-sample means */
    int pyr;       /* rate data, m = 2^pyr < AP_B: the means from the block's samples
                    * (pyr_block), level pyr; -1: from the phase (means_push) */
    int large;     /* overlapping terms from the raw values (lags beyond the small ring) */
    int hist;      /* strided terms and means from the last points at multiples of m */
    int win;       /* overlapping, every lag within the block before: the window */
    igea__ksum sum;
    long cnt;
    long nmean;    /* means pushed to the sums */
    double zc[3];  /* the last three means pushed */
    double *zb;    /* means waiting: zb[3 ..], zb[0 .. 2] the three before */
    long nzb, next_e; /* means waiting; the last point of the next mean */
    igea__ksum zs[5]; /* sums of the means z_i: z, z^2, z_{i-1} z_i, z_{i-2} z_i, z_{i-3} z_i */
    double zf[3];     /* the first three means */
    long cnext;       /* large: the term after the last one computed (-1: none yet) */
    double c1, c2;    /* large: the last difference (D or T) and running sum (S) */
    long hn;          /* hist: points kept (up to 3), newest first */
    dd hb[3];         /* their blocks' bases */
    double hl[3];     /* their local values */
} aptau;

struct igea__apass {
    int phase;
    int need_w;        /* the running sums W (modified kinds) */
    const double *rec; /* the whole record (NULL: a stream) */
    long nrec;
    long rsl, rsv;     /* blocks of the small rings of L and V */
    double *L, *V;     /* rsl blocks of AP_B (L), rsv of AP_VS (V, from the 4th) */
    double *vbuf;      /* V of the current block when no ring keeps it */
    double *lx, *vx;   /* the window: L (V) of the block before and of this one
                        * on the block before's base (2 AP_B + 1 values) */
    void *mem[6];      /* the allocations of L, V, lx, vx, buf and pz (these
                        * aligned to 64 bytes in them) */
    long cap, cap_max; /* the ring of block bases: blocks, and blocks the lags need */
    dd *Xb, *Wb;
    double *raw;       /* stream: raw values, value i at i % (rawcap AP_B) */
    long rawcap, rawcap_max;
    long reach;        /* raw values a block's terms read before its first */
    long nraw;         /* raw values received */
    long k;            /* the next block to finish */
    long N;            /* phase points so far */
    double llast, vlast; /* the finished block's last L and V */
    double off;        /* rate data: the offset removed (mean of the first block) */
    int have_off, ended;
    int bad;           /* a value was NaN or infinite */
    int ntau;
    int nlarge;        /* taus with long lags */
    long kd, nd;       /* blocks kd .. kd + nd - 1: their long-lag terms deferred */
    aptau *t;
    double *z;         /* scratch: AP_B + 3 values */
    double *buf;       /* scratch: 8 streams of AP_BUF */
    double *pz;        /* scratch of pyr_block's levels (NULL: no such tau) */
    int npyr;          /* levels pyr_block forms (the highest tau's, and one) */
    struct apsrc *src; /* stream: the values beyond the ring read back (NULL: none) */
};

static inline long mod_l(long a, long b) { return a % b; }

/* The local phase values of block blk (kept in the small ring). */
static inline double *lblk(const igea__apass *p, long blk)
{
    return p->L + (size_t)mod_l(blk, p->rsl) * AP_B;
}

static inline double *lptr(const igea__apass *p, long i)
{
    long b = i / AP_B;
    return lblk(p, b) + (i - b * AP_B);
}

/* The running sums V of block blk (AP_B + 1 values; V + 1 on a multiple of
 * 32 bytes, as the vectors of prefix2 store them). */
static inline double *vblk(const igea__apass *p, long blk)
{
    return p->V + (size_t)mod_l(blk, p->rsv) * AP_VS + 3;
}

static inline double *vptr(const igea__apass *p, long i)
{
    long b = i / AP_B;
    return vblk(p, b) + (i - b * AP_B);
}

static inline dd *xb(const igea__apass *p, long blk) { return p->Xb + mod_l(blk, p->cap); }
static inline dd *wb(const igea__apass *p, long blk) { return p->Wb + mod_l(blk, p->cap); }

/* len raw values from value index i (rate: sample, phase: point): the
 * caller's array, or the stream's ring (copied to buf where it wraps). */
static const double *src_at(const igea__apass *p, long i, long len);

static const double *raw_at(const igea__apass *p, long i, long len, double *buf)
{
    if (p->rec)
        return p->rec + i;
    if (p->src && i < p->nraw - p->rawcap * AP_B)
        return src_at(p, i, len);
    long R = p->rawcap * AP_B, s = mod_l(i, R);
    if (s + len <= R)
        return p->raw + s;
    memcpy(buf, p->raw + s, (size_t)(R - s) * sizeof(double));
    memcpy(buf + (R - s), p->raw, (size_t)(len - (R - s)) * sizeof(double));
    return buf;
}

/* ---- a stream's values read back from their file ---- */

/* When the longest lag needs more raw values than the ring of a source
 * holds (IGEA__AP_SRC_RING blocks) and the caller says where the values are
 * in a file (igea__apass_source), the ring stops there and older values are read back with pread into a few
 * windows of AP_WIN_BLOCKS blocks, one per long lag's stream (each lag reads
 * its values in order, a window at a time). Each block read back is checked
 * against the sum of the bits of the values fed (mod 2^64): a file that
 * changed, or a wrong offset or stride, is an error, never other values
 * [D]. An error is kept (src->err): the pass goes on over zeros, and the
 * feed or the end return it. */
#define AP_WIN_BLOCKS 32 /* blocks of a window (256 KB) */
#define AP_WIN_MAX 64    /* windows at most */
#define AP_SRC_CHUNK (1 << 20) /* bytes of one pread of a strided column */

static void *grow_array(void *p, size_t n, size_t sz);

struct apsrc {
    int fd;
    long stride;         /* bytes from one value to the next */
    double off;          /* byte offset of value 0 */
    int nwin;
    double *win;         /* nwin windows of AP_WIN_BLOCKS AP_B values */
    long *wfirst, *wlen; /* each window's first value and how many it holds */
    unsigned long *wuse, clock;
    unsigned char *tmp;  /* AP_SRC_CHUNK bytes (stride > 8) */
    uint64_t *ck;        /* per whole block fed: the sum of its values' bits */
    long nck, capck;
    uint64_t cur;        /* the block being fed: its partial sum */
    int err;             /* 0, IGEA_EREAD or IGEA_ENOMEM */
};

static void src_free(struct apsrc *s)
{
    if (!s)
        return;
    free(s->win);
    free(s->wfirst);
    free(s->wuse);
    free(s->tmp);
    free(s->ck);
    free(s);
}

static uint64_t bits_sum(const double *v, long n)
{
    uint64_t a = 0;
    for (long j = 0; j < n; j++) {
        uint64_t u;
        memcpy(&u, v + j, sizeof u);
        a += u;
    }
    return a;
}

/* The checksums of the n values v fed after the first nraw0. */
static void src_fed(struct apsrc *s, long nraw0, const double *v, long n)
{
    long j = 0;
    while (j < n && !s->err) {
        long in = (nraw0 + j) % AP_B, c = IGEA_MIN(n - j, AP_B - in);
        s->cur += bits_sum(v + j, c);
        j += c;
        if (in + c == AP_B) { /* a whole block */
            if (s->nck == s->capck) {
                long nc = s->capck ? 2 * s->capck : 1024;
                uint64_t *k = grow_array(s->ck, (size_t)nc, sizeof *k);
                if (!k) {
                    s->err = IGEA_ENOMEM;
                    return;
                }
                s->ck = k;
                s->capck = nc;
            }
            s->ck[s->nck++] = s->cur;
            s->cur = 0;
        }
    }
}

/* cnt values from value first into w (pread; strided: through tmp).
 * 0 or IGEA_EREAD. */
static int src_read(struct apsrc *s, long first, long cnt, double *w)
{
    long long pos = (long long)s->off + (long long)first * s->stride;
    if (s->stride == (long)sizeof(double))
        return igea__pread_full(s->fd, w, (size_t)cnt * sizeof(double), pos);
    long per = AP_SRC_CHUNK / s->stride; /* values per pread (stride <= AP_SRC_CHUNK / 8) */
    for (long j = 0; j < cnt; j += per) {
        long c = IGEA_MIN(per, cnt - j);
        int st = igea__pread_full(s->fd, s->tmp, (size_t)(c - 1) * (size_t)s->stride + sizeof(double),
                                  pos + (long long)j * s->stride);
        if (st)
            return st;
        for (long q = 0; q < c; q++)
            memcpy(w + j + q, s->tmp + (size_t)q * (size_t)s->stride, sizeof(double));
    }
    return 0;
}

/* len values from value i, older than the ring: from the window that holds
 * them, or the least recently used one filled from i's block on (whole
 * blocks fed, each checked). On an error, zeros. */
static const double *src_at(const igea__apass *p, long i, long len)
{
    struct apsrc *s = p->src;
    int lru = 0;
    s->clock++;
    for (int w = 0; w < s->nwin; w++) {
        if (s->wlen[w] > 0 && s->wfirst[w] <= i && i + len <= s->wfirst[w] + s->wlen[w]) {
            s->wuse[w] = s->clock;
            return s->win + (size_t)w * AP_WIN_BLOCKS * AP_B + (i - s->wfirst[w]);
        }
        if (s->wuse[w] < s->wuse[lru])
            lru = w;
    }
    double *w = s->win + (size_t)lru * AP_WIN_BLOCKS * AP_B;
    long b0 = i / AP_B, nb = IGEA_MIN((long)AP_WIN_BLOCKS, s->nck - b0);
    int st = s->err;
    if (!st && (nb < 1 || i + len > (b0 + nb) * AP_B))
        st = IGEA_EREAD; /* cannot happen: the ring holds the newest blocks */
    if (!st)
        st = src_read(s, b0 * AP_B, nb * AP_B, w);
    for (long b = 0; !st && b < nb; b++)
        if (bits_sum(w + b * AP_B, AP_B) != s->ck[b0 + b])
            st = IGEA_EREAD;
    s->wuse[lru] = s->clock;
    if (st) {
        s->err = st;
        s->wlen[lru] = 0;
        memset(w, 0, (size_t)AP_WIN_BLOCKS * AP_B * sizeof(double));
        return w;
    }
    s->wfirst[lru] = b0 * AP_B;
    s->wlen[lru] = nb * AP_B;
    return w + (i - b0 * AP_B);
}

void igea__apass_free(igea__apass *p)
{
    if (!p)
        return;
    for (int i = 0; i < 6; i++)
        free(p->mem[i]);
    free(p->vbuf);
    free(p->Xb);
    free(p->Wb);
    free(p->raw);
    src_free(p->src);
    for (int j = 0; p->t && j < p->ntau; j++)
        free(p->t[j].zb);
    free(p->t);
    free(p->z);
    free(p);
}

/* realloc of n items of size sz (NULL on overflow or failure, p kept). */
static void *grow_array(void *p, size_t n, size_t sz)
{
    return n > (size_t)-1 / sz ? NULL : realloc(p, n * sz);
}

/* The ring of bases grown to newcap blocks, keeping blocks k - cap .. k
 * (k the block being finished). Before the ring has wrapped the arrays are
 * extended in place. */
static int base_grow(igea__apass *p, long newcap)
{
    if (p->k < p->cap) {
        dd *X = grow_array(p->Xb, (size_t)newcap, sizeof(dd));
        if (X)
            p->Xb = X;
        dd *W = X ? grow_array(p->Wb, (size_t)newcap, sizeof(dd)) : NULL;
        if (!W)
            return IGEA_ENOMEM;
        p->Wb = W;
        p->cap = newcap;
        return 0;
    }
    dd *X = malloc((size_t)newcap * sizeof(dd)), *W = malloc((size_t)newcap * sizeof(dd));
    if (!X || !W) {
        free(X);
        free(W);
        return IGEA_ENOMEM;
    }
    for (long b = p->k - p->cap; b < p->k; b++) {
        X[b % newcap] = p->Xb[b % p->cap];
        W[b % newcap] = p->Wb[b % p->cap];
    }
    free(p->Xb);
    free(p->Wb);
    p->Xb = X;
    p->Wb = W;
    p->cap = newcap;
    return 0;
}

/* The stream's ring of raw values grown to newcap blocks, keeping the last
 * rawcap AP_B values (in place before it has wrapped). */
static int raw_grow(igea__apass *p, long newcap)
{
    size_t R = (size_t)p->rawcap * AP_B, Rn = (size_t)newcap * AP_B;
    if ((size_t)p->nraw <= R) {
        double *r = grow_array(p->raw, Rn, sizeof(double));
        if (!r)
            return IGEA_ENOMEM;
        p->raw = r;
        p->rawcap = newcap;
        return 0;
    }
    double *r = igea__dalloc(Rn);
    if (!r)
        return IGEA_ENOMEM;
    for (long i = p->nraw - (long)R; i < p->nraw; i++)
        r[(size_t)i % Rn] = p->raw[(size_t)i % R];
    free(p->raw);
    p->raw = r;
    p->rawcap = newcap;
    return 0;
}

/* n doubles from a multiple of 64 bytes (the vectors' stores within one
 * cache line), *mem the allocation to free (NULL on failure). */
static double *dalloc64(size_t n, void **mem)
{
    double *a = n > (size_t)-1 / sizeof(double) - 8 ? NULL : igea__dalloc(n + 8);
    *mem = a;
    return a ? a + ((64 - (size_t)((uintptr_t)a & 63)) & 63) / sizeof(double) : NULL;
}

static int apass_alloc(int phase, int ntau, const igea__aptau_spec *spec, const double *rec,
                       long nrec, long nhint, igea__apass **out)
{
    igea__apass *p = calloc(1, sizeof *p);
    if (!p)
        return IGEA_ENOMEM;
    p->phase = phase;
    p->rec = rec;
    p->nrec = nrec;
    p->ntau = ntau;
    p->t = calloc((size_t)(ntau > 0 ? ntau : 1), sizeof(aptau));
    p->z = igea__dalloc(AP_B + 3);
    p->buf = dalloc64(8 * (size_t)AP_BUF, &p->mem[4]);
    if (!p->t || !p->z || !p->buf) {
        igea__apass_free(p);
        return IGEA_ENOMEM;
    }
    long span = 1, lspan = 0, rsl = 5, rsv = 0;
    int wl = 0, wv = 0;
    for (int j = 0; j < ntau; j++) {
        aptau *t = &p->t[j];
        t->m = spec[j].m;
        t->type = spec[j].type;
        t->stride = spec[j].stride;
        /* (a whole record's tau with fewer than 32 means: no type from them) */
        t->acf = spec[j].acf != 0 && !(rec && nrec / t->m < 32);
        t->pyr = -1;
        if (t->acf && !phase && t->m < AP_B && (t->m & (t->m - 1)) == 0) {
            int l = 0;
            while ((1L << l) < t->m)
                l++;
            t->pyr = l;
            p->npyr = IGEA_MAX(p->npyr, l + 1);
        }
        t->span = (t->type == IGEA__AP_AV ? 2 : 3) * t->m;
        t->cnext = -1;
        /* the overlapping lags that the small ring does not hold */
        long blocks = t->span / AP_B + 3;
        t->large = t->stride && t->m > 1 && blocks > AP_RS_MAX;
        t->hist = t->m >= AP_B && (t->acf || !(t->stride || t->m == 1));
        if (t->acf) { /* the three means before, 255 waiting, a block's */
            t->next_e = t->m;
            if (!(t->zb = igea__dalloc(3 + 255 + AP_B / (size_t)t->m + 1))) {
                igea__apass_free(p);
                return IGEA_ENOMEM;
            }
        }
        if (t->span > span)
            span = t->span;
        if (t->large && t->span > lspan)
            lspan = t->span;
        p->nlarge += t->large;
        if ((t->stride || t->m == 1) && !t->large) { /* overlapping: the small ring */
            t->win = t->span <= AP_B;
            if (t->type == IGEA__AP_MV)
                rsv = IGEA_MAX(rsv, blocks);
            else
                rsl = IGEA_MAX(rsl, blocks);
            if (t->win && t->type == IGEA__AP_MV)
                wv = 1;
            else if (t->win)
                wl = 1;
        }
        p->need_w = p->need_w || t->type == IGEA__AP_MV;
    }
    long nb = nhint > 0 ? nhint / AP_B + 2 : 0; /* blocks of the record, and one */
    if (nb > 0) {
        rsl = IGEA_MIN(rsl, nb);
        rsv = IGEA_MIN(rsv, nb);
    }
    if (p->need_w)
        rsv = IGEA_MAX(rsv, 2); /* the window's block before */
    p->rsl = rsl;
    p->rsv = rsv;
    p->lx = wl ? dalloc64(2 * AP_B + 1, &p->mem[2]) : NULL;
    p->vx = wv ? dalloc64(2 * AP_B + 2, &p->mem[3]) : NULL;
    if (wv && !p->lx)
        p->lx = NULL;
    p->L = dalloc64((size_t)rsl * AP_B, &p->mem[0]);
    p->V = rsv ? dalloc64((size_t)rsv * AP_VS, &p->mem[1]) : NULL;
    p->vbuf = p->need_w && !rsv ? igea__dalloc(AP_B + 1) : NULL;
    /* bases: back to the longest lag, plus the current block */
    p->cap_max = IGEA_MAX(span / AP_B + 4 + (lspan ? AP_DEFER : 0), IGEA_MAX(rsl, rsv) + 1);
    long c0 = p->cap_max;
    if (nb > 0 && nb + 1 < c0)
        c0 = nb + 1;
    if (!rec && nhint <= 0 && c0 > 16)
        c0 = 16;
    /* raw values before a block's first that its terms read (the lag,
     * the sample before it, the block of an anchor), and the stream's ring */
    p->reach = lspan ? lspan + (AP_DEFER + 1) * AP_B + 1 : 1;
    p->rawcap_max = (p->reach + AP_B - 1) / AP_B + 4;
    if (p->npyr)
        p->pz = dalloc64(AP_B + 8 * AP_NLEV, &p->mem[5]);
    int st = !p->L || (p->npyr && !p->pz) || (rsv && !p->V) || (p->need_w && !rsv && !p->vbuf) || (wl && !p->lx) ||
                     (wv && !p->vx)
                 ? IGEA_ENOMEM
                 : 0;
    if (!st)
        st = base_grow(p, c0);
    if (!st && !rec)
        st = raw_grow(p, IGEA_MIN(p->rawcap_max, nhint <= 0 ? 16 : nhint / AP_B + 4));
    if (st) {
        igea__apass_free(p);
        return st;
    }
    *out = p;
    return 0;
}

int igea__apass_new(int phase, int ntau, const igea__aptau_spec *spec, long nhint,
                    igea__apass **out)
{
    return apass_alloc(phase, ntau, spec, NULL, 0, nhint, out);
}

int igea__apass_source(igea__apass *p, int fd, double off, long stride, long ring)
{
    if (p->rec || p->nraw > 0 || p->src)
        return -1;
    ring = IGEA_MAX(ring, AP_DEFER + 8); /* the deferred blocks stay in the ring */
    if (p->rawcap_max <= ring)
        return 0; /* the ring holds every lag: nothing is read back */
    struct apsrc *s = calloc(1, sizeof *s);
    if (!s)
        return IGEA_ENOMEM;
    s->fd = fd;
    s->off = off;
    s->stride = stride;
    /* a window per long lag's stream (the lags beyond the ring), and spares */
    int streams = 0;
    for (int j = 0; j < p->ntau; j++)
        if (p->t[j].large && p->t[j].span + 2 * AP_B > (ring - 4) * AP_B)
            streams += p->t[j].type == IGEA__AP_AV ? 2 : 3;
    s->nwin = IGEA_MIN(AP_WIN_MAX, IGEA_MAX(8, streams + 4));
    s->win = igea__dalloc((size_t)s->nwin * AP_WIN_BLOCKS * AP_B);
    s->wfirst = malloc(2 * (size_t)s->nwin * sizeof(long));
    s->wuse = calloc((size_t)s->nwin, sizeof(unsigned long));
    s->tmp = stride > (long)sizeof(double) ? malloc(AP_SRC_CHUNK) : NULL;
    if (!s->win || !s->wfirst || !s->wuse || (stride > (long)sizeof(double) && !s->tmp)) {
        src_free(s);
        return IGEA_ENOMEM;
    }
    s->wlen = s->wfirst + s->nwin;
    for (int w = 0; w < s->nwin; w++)
        s->wfirst[w] = s->wlen[w] = 0;
    p->src = s;
    p->rawcap_max = ring;
    return 0;
}

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

#if AP_VEC
#if defined(__clang__)
#define AP_SHUF(a, b, i, j, k, l) __builtin_shufflevector(a, b, i, j, k, l)
#else
typedef long long ap_i4 __attribute__((vector_size(32)));
#define AP_SHUF(a, b, i, j, k, l) __builtin_shuffle(a, b, (ap_i4){i, j, k, l})
#endif
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
#define AP_VLANES8(VEXPR, EXPR) AP_VLANES8N(VEXPR, EXPR, (void)0)
/* NEXT: what the kernel carries on to the next eight values */
#define AP_VLANES8N(VEXPR, EXPR, NEXT)                                                    \
    ap_v4 va = {0, 0, 0, 0}, vb = {0, 0, 0, 0};                                           \
    long i = 0;                                                                           \
    for (; i + 8 <= len; i += 8) {                                                        \
        ap_v4 ta = VEXPR(0), tb = VEXPR(4);                                               \
        va += ta * ta;                                                                    \
        vb += tb * tb;                                                                    \
        NEXT;                                                                             \
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
    /* (the indices i + l as doubles carried in two vectors: the same values) */
    ap_v4 lo = {0, 1, 2, 3}, hi = {4, 5, 6, 7};
#define AP_MV_V(l)                                                                        \
    (((AP_LD(v0 + i + l) - AP_LD(v3 + i + l)) -                                           \
      3.0 * (AP_LD(v1 + i + l) - AP_LD(v2 + i + l))) +                                    \
     (A + (l ? hi : lo) * Bc))
    AP_VLANES8N(AP_MV_V, AP_MV_T, (lo += 8.0, hi += 8.0));
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

/* ---- long lags: differences of the raw values and their running sums ---- */

#if AP_VEC
#define AP_STV(p, v) (*(ap_v4 *)(void *)(p) = (v))
#endif

/* g[i] = (a0[i] - a1[i]) - (a1[i] - a2[i]): the second difference of the
 * raw values at lag m (its running sum is the Allan term's difference of
 * the phase). */
AP_CLONES static void inc_av(const double *a0, const double *a1, const double *a2, long len,
                             double *g)
{
    long i = 0;
#if AP_VEC
    for (; i + 4 <= len; i += 4) {
        ap_v4 b = AP_LD(a1 + i);
        AP_STV(g + i, (AP_LD(a0 + i) - b) - (b - AP_LD(a2 + i)));
    }
#endif
    for (; i < len; i++)
        g[i] = (a0[i] - a1[i]) - (a1[i] - a2[i]);
}

/* h[i] = (a0[i] - a3[i]) - 3 (a1[i] - a2[i]): the third difference. */
AP_CLONES static void inc_hv(const double *a0, const double *a1, const double *a2,
                             const double *a3, long len, double *h)
{
    long i = 0;
#if AP_VEC
    for (; i + 4 <= len; i += 4)
        AP_STV(h + i, (AP_LD(a0 + i) - AP_LD(a3 + i)) - 3.0 * (AP_LD(a1 + i) - AP_LD(a2 + i)));
#endif
    for (; i < len; i++)
        h[i] = (a0[i] - a3[i]) - 3.0 * (a1[i] - a2[i]);
}

/* The running sum of len values from v0: v_i = v_{i-1} + inc[i-1] for i =
 * 1, 2, 3 and v_i = v_{i-4} + ((inc[i-4] + inc[i-3]) + (inc[i-2] + inc[i-1]))
 * from i = 4 on (four lanes, each a running sum of sums of four increments:
 * a vector of four advances in one addition; inc[0 .. len-2] are read).
 * SQ: returns the sum of the squares (lane i mod 4 over the first
 * 4 floor(len/4) values, the rest in lane 0, ((s0 + s1) + (s2 + s3)));
 * otherwise stores the values in out. *last = v_{len-1}. */
#if AP_VEC
#define AP_CHAIN_VEC(SQ)                                                                  \
    ap_v4 V = {w0, w1, w2, w3}, S = {0, 0, 0, 0};                                         \
    for (long q = 0;; q++) {                                                              \
        if (SQ)                                                                           \
            S += V * V;                                                                   \
        else                                                                              \
            AP_STV(out + 4 * q, V);                                                       \
        if (q + 1 == n4)                                                                  \
            break;                                                                        \
        const double *c = inc + 4 * q;                                                    \
        V += (AP_LD(c) + AP_LD(c + 1)) + (AP_LD(c + 2) + AP_LD(c + 3));                   \
    }                                                                                     \
    s0 = S[0], s1 = S[1], s2 = S[2], s3 = S[3];                                           \
    w0 = V[0], w1 = V[1], w2 = V[2], w3 = V[3]
#else
#define AP_CHAIN_VEC(SQ)                                                                  \
    for (long q = 0;; q++) {                                                              \
        if (SQ) {                                                                         \
            s0 += w0 * w0;                                                                \
            s1 += w1 * w1;                                                                \
            s2 += w2 * w2;                                                                \
            s3 += w3 * w3;                                                                \
        } else {                                                                          \
            out[4 * q] = w0, out[4 * q + 1] = w1, out[4 * q + 2] = w2, out[4 * q + 3] = w3; \
        }                                                                                 \
        if (q + 1 == n4)                                                                  \
            break;                                                                        \
        const double *c = inc + 4 * q;                                                    \
        w0 += (c[0] + c[1]) + (c[2] + c[3]);                                              \
        w1 += (c[1] + c[2]) + (c[3] + c[4]);                                              \
        w2 += (c[2] + c[3]) + (c[4] + c[5]);                                              \
        w3 += (c[3] + c[4]) + (c[5] + c[6]);                                              \
    }
#endif
#define AP_CHAIN(NAME, SQ)                                                                \
    AP_CLONES static double NAME(double v0, const double *inc, long len, double *out,     \
                                 double *last)                                            \
    {                                                                                     \
        double s0 = 0, s1 = 0, s2 = 0, s3 = 0, v = v0;                                    \
        long n4 = len / 4, i = 0;                                                         \
        (void)out;                                                                        \
        if (n4 > 0) {                                                                     \
            double w0 = v0, w1 = w0 + inc[0], w2 = w1 + inc[1], w3 = w2 + inc[2];         \
            AP_CHAIN_VEC(SQ);                                                             \
            double wl[4] = {w0, w1, w2, w3};                                              \
            v = w3;                                                                       \
            for (i = 4 * n4; i < len; i++) {                                              \
                const double *c = inc + i - 4;                                            \
                v = wl[i - 4 * n4] + ((c[0] + c[1]) + (c[2] + c[3]));                     \
                if (SQ)                                                                   \
                    s0 += v * v;                                                          \
                else                                                                      \
                    out[i] = v;                                                           \
            }                                                                             \
        } else {                                                                          \
            for (; i < len; i++) {                                                        \
                if (i)                                                                    \
                    v += inc[i - 1];                                                      \
                if (SQ)                                                                   \
                    s0 += v * v;                                                          \
                else                                                                      \
                    out[i] = v;                                                           \
            }                                                                             \
        }                                                                                 \
        *last = v;                                                                        \
        return (s0 + s1) + (s2 + s3);                                                     \
    }
AP_CHAIN(chain_sq, 1)
AP_CHAIN(chain_st, 0)
#undef AP_CHAIN
#undef AP_CHAIN_VEC

/* chain_st from T0 over inc (len values T) and chain_sq from S0 over those
 * values in one loop (the same sums bit for bit: the T lanes shifted by one,
 * two and three values are the unaligned loads chain_sq makes), len >= 4:
 * two recurrences in flight instead of one after the other. Returns the sum
 * of the squares of S; *tlast, *slast the last T and S. */
AP_CLONES static double chain_ts(double T0, double S0, const double *inc, long len,
                                 double *tlast, double *slast)
{
    long n4 = len / 4;
    double t[8], s0, s1, s2, s3;
    double w0 = T0, w1 = w0 + inc[0], w2 = w1 + inc[1], w3 = w2 + inc[2];
    double u0 = S0, u1 = u0 + w0, u2 = u1 + w1, u3 = u2 + w2;
#if AP_VEC
    ap_v4 VT = {w0, w1, w2, w3}, VS = {u0, u1, u2, u3}, SS = {0, 0, 0, 0};
    for (long q = 0;; q++) {
        SS += VS * VS;
        if (q + 1 == n4)
            break;
        const double *c = inc + 4 * q;
        ap_v4 VN = VT + ((AP_LD(c) + AP_LD(c + 1)) + (AP_LD(c + 2) + AP_LD(c + 3)));
        ap_v4 h2 = AP_SHUF(VT, VN, 2, 3, 4, 5), h1 = AP_SHUF(VT, h2, 1, 4, 3, 6);
        ap_v4 h3 = AP_SHUF(h2, VN, 1, 4, 3, 6);
        VS += (VT + h1) + (h2 + h3);
        VT = VN;
    }
    s0 = SS[0], s1 = SS[1], s2 = SS[2], s3 = SS[3];
    for (int l = 0; l < 4; l++)
        t[l] = VT[l], t[4 + l] = VS[l];
#else
    s0 = s1 = s2 = s3 = 0.0;
    for (long q = 0;; q++) {
        s0 += u0 * u0;
        s1 += u1 * u1;
        s2 += u2 * u2;
        s3 += u3 * u3;
        if (q + 1 == n4)
            break;
        const double *c = inc + 4 * q;
        double n0 = w0 + ((c[0] + c[1]) + (c[2] + c[3]));
        double n1 = w1 + ((c[1] + c[2]) + (c[3] + c[4]));
        double n2 = w2 + ((c[2] + c[3]) + (c[4] + c[5]));
        double n3 = w3 + ((c[3] + c[4]) + (c[5] + c[6]));
        u0 += (w0 + w1) + (w2 + w3);
        u1 += (w1 + w2) + (w3 + n0);
        u2 += (w2 + w3) + (n0 + n1);
        u3 += (w3 + n0) + (n1 + n2);
        w0 = n0, w1 = n1, w2 = n2, w3 = n3;
    }
    t[0] = w0, t[1] = w1, t[2] = w2, t[3] = w3, t[4] = u0, t[5] = u1, t[6] = u2, t[7] = u3;
#endif
    /* the tails (fewer than four values): T then S, as the two chains do */
    double tt[7], tv = t[3], sv = t[7];
    for (int l = 0; l < 4; l++)
        tt[l] = t[l];
    for (long i = 4 * n4; i < len; i++) {
        const double *c = inc + i - 4;
        tv = tt[i - 4 * n4 + 4 - 4] + ((c[0] + c[1]) + (c[2] + c[3]));
        tt[i - 4 * n4 + 4] = tv;
    }
    for (long i = 4 * n4; i < len; i++) {
        const double *c = tt + (i - 4 * n4);
        sv = t[4 + i - 4 * n4] + ((c[0] + c[1]) + (c[2] + c[3]));
        s0 += sv * sv;
    }
    *tlast = tv;
    *slast = sv;
    return (s0 + s1) + (s2 + s3);
}

#if AP_VEC
/* The modified kind's long lag for rate data with the increments formed in
 * the same loop: a[q] the raw values at lag q m from the block's first term
 * (len + 8 of each, len >= 4), h_i = (a0 - a3) - 3 (a1 - a2) as inc_hv forms
 * them, the four values after a vector's from the next one by shuffles. The
 * loop is skewed: while S steps from q to q + 1, T steps from q + 1 and the
 * increments are formed for q + 3, so that each step's operands are ready
 * (at most eight values past len are read, none used). The same sums as
 * inc_hv then chain_ts bit for bit. */
AP_CLONES static double chain_hts(const double *const *a, double T0, double S0, long len,
                                  double *tlast, double *slast)
{
    const double *a0 = a[0], *a1 = a[1], *a2 = a[2], *a3 = a[3];
#define AP_HV4(k) ((AP_LD(a0 + (k)) - AP_LD(a3 + (k))) - 3.0 * (AP_LD(a1 + (k)) - AP_LD(a2 + (k))))
/* R = the sums of four from each lane of X on (Y the vector after X) */
#define AP_SUM4(X, Y, R)                                                                  \
    {                                                                                     \
        ap_v4 g2 = AP_SHUF(X, Y, 2, 3, 4, 5), g1 = AP_SHUF(X, g2, 1, 4, 3, 6);            \
        ap_v4 g3 = AP_SHUF(g2, Y, 1, 4, 3, 6);                                            \
        R = (X + g1) + (g2 + g3);                                                         \
    }
    long n4 = len / 4;
    ap_v4 H = AP_HV4(0), H1 = AP_HV4(4), D;
    double w0 = T0, w1 = w0 + H[0], w2 = w1 + H[1], w3 = w2 + H[2];
    double u0 = S0, u1 = u0 + w0, u2 = u1 + w1, u3 = u2 + w2;
    ap_v4 VT = {w0, w1, w2, w3}, VS = {u0, u1, u2, u3}, SS = {0, 0, 0, 0}, VT1;
    AP_SUM4(H, H1, D);
    VT1 = VT + D;           /* T of step 1 */
    H = AP_HV4(8);
    AP_SUM4(H1, H, D);      /* the increments' sums of step 1 to 2 */
    for (long q = 0;; q++) {
        /* VS: S of step q; VT, VT1: T of steps q and q + 1; D: the sums from
         * q + 1 to q + 2; H: h of step q + 2 */
        SS += VS * VS;
        if (q + 1 == n4)
            break;
        ap_v4 E, HN = AP_HV4(4 * q + 12), VT2 = VT1 + D;
        AP_SUM4(VT, VT1, E);
        VS += E;
        AP_SUM4(H, HN, D);
        H = HN;
        VT = VT1;
        VT1 = VT2;
    }
#undef AP_SUM4
#undef AP_HV4
    /* the tails (fewer than four values), as chain_ts */
    double hh[7], tt[7], tv = VT[3], sv = VS[3];
    double s0 = SS[0], s1 = SS[1], s2 = SS[2], s3 = SS[3];
    long b = 4 * n4 - 4;
    for (int l = 0; l < 4; l++)
        tt[l] = VT[l];
    for (long i = b; i < len - 1; i++)
        hh[i - b] = (a0[i] - a3[i]) - 3.0 * (a1[i] - a2[i]);
    for (long i = b + 4; i < len; i++) {
        const double *c = hh + (i - 4 - b);
        tv = tt[i - 4 - b] + ((c[0] + c[1]) + (c[2] + c[3]));
        tt[i - b] = tv;
    }
    for (long i = b + 4; i < len; i++) {
        const double *c = tt + (i - 4 - b);
        sv = VS[i - 4 - b] + ((c[0] + c[1]) + (c[2] + c[3]));
        s0 += sv * sv;
    }
    *tlast = tv;
    *slast = sv;
    return (s0 + s1) + (s2 + s3);
}
#endif

/* d[i] = v[i] - o. */
AP_CLONES static void sub_off(const double *v, long len, double o, double *d)
{
    long i = 0;
#if AP_VEC
    for (; i + 4 <= len; i += 4)
        AP_STV(d + i, AP_LD(v + i) - o);
#endif
    for (; i < len; i++)
        d[i] = v[i] - o;
}

/* out[i] = (c + i s) + v[i]. */
AP_CLONES static void shift_add(const double *v, long len, double s, double c, double *out)
{
    long i = 0;
#if AP_VEC
    const ap_v4 i0 = {0, 1, 2, 3};
    for (; i + 4 <= len; i += 4)
        AP_STV(out + i, (c + ((double)i + i0) * s) + AP_LD(v + i));
#endif
    for (; i < len; i++)
        out[i] = (c + (double)i * s) + v[i];
}

/* out[j] = (V[j] - vl) + (AP_B - j) dX, j < AP_B: the running sums of the
 * block before on the next block's base. */
AP_CLONES static void vx_prev(const double *V, double vl, double dX, double *out)
{
    long j = 0;
#if AP_VEC
    const ap_v4 j0 = {0, 1, 2, 3};
    for (; j + 4 <= AP_B; j += 4)
        AP_STV(out + j, (AP_LD(V + j) - vl) + ((double)(AP_B - j) - j0) * dX);
#else
    for (; j < AP_B; j++)
        out[j] = (V[j] - vl) + (double)(AP_B - j) * dX;
#endif
}

/* Sum of (v[i] - o) over len values, four lanes (i mod 4, the rest in lane
 * 0). */
static double lsum(const double *v, long len, double o)
{
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    long i = 0;
    for (; i + 4 <= len; i += 4) {
        s0 += v[i] - o;
        s1 += v[i + 1] - o;
        s2 += v[i + 2] - o;
        s3 += v[i + 3] - o;
    }
    for (; i < len; i++)
        s0 += v[i] - o;
    return (s0 + s1) + (s2 + s3);
}

/* Sum of (len - i) (v[i] - o) over len values (the running sums of a
 * running sum), four lanes as lsum. */
static double wsum(const double *v, long len, double o)
{
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    long i = 0;
    for (; i + 4 <= len; i += 4) {
        s0 += (double)(len - i) * (v[i] - o);
        s1 += (double)(len - i - 1) * (v[i + 1] - o);
        s2 += (double)(len - i - 2) * (v[i + 2] - o);
        s3 += (double)(len - i - 3) * (v[i + 3] - o);
    }
    for (; i < len; i++)
        s0 += (double)(len - i) * (v[i] - o);
    return (s0 + s1) + (s2 + s3);
}

/* The phase X_t (double-double): its block's base and, off the block
 * grid, the rate samples since (phase data: the point itself). */
static dd x_at(const igea__apass *p, long t, double *buf)
{
    long b = t / AP_B, j = t - b * AP_B;
    if (j == 0)
        return *xb(p, b);
    if (p->phase) {
        dd r = {*raw_at(p, t, 1, buf), 0.0};
        return r;
    }
    return dd_add_d(*xb(p, b), lsum(raw_at(p, b * AP_B, j, buf), j, p->off));
}

/* The running sum W_t = sum of X_r, r < t (double-double): W_b + j X_b +
 * the sum of the j local values of the block before t. */
static dd w_at(const igea__apass *p, long t, double *buf)
{
    long b = t / AP_B, j = t - b * AP_B;
    dd w = dd_add(*wb(p, b), dd_mul_d(*xb(p, b), (double)j));
    if (j == 0)
        return w;
    if (p->phase) /* sum of (x_i - x_b) over the block's first j points */
        return dd_add_d(w, lsum(raw_at(p, b * AP_B, j, buf), j, xb(p, b)->hi));
    /* L_i = sum of the samples bB .. bB + i - 1: sum over i < j of L_i */
    if (j == 1)
        return w;
    return dd_add_d(w, wsum(raw_at(p, b * AP_B, j - 1, buf), j - 1, p->off));
}

/* Coefficients of the difference at lags 0, m, 2m, 3m. */
static const double cAV[4] = {1, -2, 1, 0}, cHV[4] = {1, -3, 3, -1};

/* The exact difference of the phase (c = cAV or cHV) or of its running
 * sum (w) at e, from the bases (double-double). */
static double anchor(const igea__apass *p, const aptau *t, long e, const double *c, int w)
{
    int np = c[3] != 0.0 ? 4 : 3;
    dd v[4];
    for (int q = 0; q < np; q++) {
        long i = e - q * t->m;
        v[q] = w ? w_at(p, i, p->buf) : x_at(p, i, p->buf);
    }
    return dd_get(np == 3 ? dd_diff2(v) : dd_diff3(v));
}

/* The sum of the squared overlapping terms e0 <= e < e1 (one block) of a
 * long lag. Phase data (Allan, Hadamard): the differences of the raw
 * points. Otherwise the running sums of the raw values' differences (rate
 * data: the phase's difference D or T from the samples' one; the modified
 * kinds: S from T) from an exact anchor at e0 (every block for lags on the
 * block grid, every AP_REANCHOR blocks off it, and at the first term) or
 * continued from the block before. */
static double large_block(igea__apass *p, aptau *t, long e0, long e1)
{
    long m = t->m, len = e1 - e0;
    int np = t->type == IGEA__AP_AV ? 3 : 4;
    double *bf = p->buf, *s[4], *inc = bf + 4 * AP_BUF, *tv = bf + 5 * AP_BUF;
    const double *a[4];
    double tot;
    for (int q = 0; q < 4; q++)
        s[q] = bf + q * AP_BUF;
    if (p->phase && t->type != IGEA__AP_MV) {
        for (int q = 0; q < np; q++)
            a[q] = raw_at(p, e0 - q * m, len, s[q]);
        return np == 3 ? seg_av(a[0], a[1], a[2], len, 0.0)
                       : seg_hv(a[0], a[1], a[2], a[3], len, 0.0);
    }
    int cont = t->cnext == e0;
    int exact = !cont || m % AP_B == 0 || (e0 / AP_B) % AP_REANCHOR == 0;
#if AP_VEC
    if (!p->phase && t->type == IGEA__AP_MV && len >= 4 && e1 + 8 <= p->nraw) {
        /* (every increment the block's terms need is there, and eight raw
         * values more: the T and S of the block from the raw values in one
         * loop) */
        double T0, v0 = exact ? anchor(p, t, e0, cHV, 1) : t->c2 + t->c1;
        if (exact)
            T0 = anchor(p, t, e0, cHV, 0);
        else { /* T_{e0} = T_{e0-1} + the increment at e0 - 1 */
            double y[4];
            for (int q = 0; q < 4; q++)
                y[q] = *raw_at(p, e0 - 1 - q * m, 1, s[q]);
            T0 = t->c1 + ((y[0] - y[3]) - 3.0 * (y[1] - y[2]));
        }
        for (int q = 0; q < 4; q++)
            a[q] = raw_at(p, e0 - q * m, len + 8, s[q]);
        tot = chain_hts(a, T0, v0, len, &t->c1, &t->c2);
        t->cnext = e1;
        return tot;
    }
#endif
    /* the increments from e0 - 1 (continued) or e0 (the first term) to
     * e1 - 2 (rate data: not past the last sample, N - 2) */
    long i0 = cont ? e0 - 1 : e0, ilast = e1 - 2;
    if (!p->phase && ilast > p->N - 2)
        ilast = p->N - 2;
    long ni = ilast + 1 - i0;
    if (ni > 0) {
        for (int q = 0; q < np; q++)
            a[q] = raw_at(p, i0 - q * m, ni, s[q]);
        if (np == 3)
            inc_av(a[0], a[1], a[2], ni, inc);
        else
            inc_hv(a[0], a[1], a[2], a[3], ni, inc);
    }
    const double *in = inc + (cont ? 1 : 0); /* the increment at e0 */
    double last, v0;
    if (t->type == IGEA__AP_AV || t->type == IGEA__AP_HV) { /* rate data */
        const double *c = t->type == IGEA__AP_AV ? cAV : cHV;
        v0 = exact ? anchor(p, t, e0, c, 0) : t->c1 + inc[0];
        tot = chain_sq(v0, in, len, NULL, &last);
        t->c1 = last;
    } else {
        const double *tt; /* T at e0 .. e1 - 1 */
        if (p->phase) {
            tt = in; /* the points' third difference is T itself */
            v0 = exact ? anchor(p, t, e0, cHV, 1) : t->c2 + inc[0];
        } else {
            /* T at e0 .. e0 + nT - 1: all of the block's but, at the end of
             * the record, the last (only S needs it: S_N = S_{N-1} + T_{N-1}) */
            long nT = cont && ni < 1 ? 0 : IGEA_MIN(len, ni - cont + 1);
            v0 = exact ? anchor(p, t, e0, cHV, 1) : t->c2 + t->c1;
            if (nT == len && len >= 4) { /* T and S in one loop */
                double T0 = exact ? anchor(p, t, e0, cHV, 0) : t->c1 + inc[0];
                tot = chain_ts(T0, v0, in, len, &t->c1, &t->c2);
                t->cnext = e1;
                return tot;
            }
            if (nT > 0) {
                double T0 = exact ? anchor(p, t, e0, cHV, 0) : t->c1 + inc[0];
                chain_st(T0, in, nT, tv, &last);
                t->c1 = last;
            }
            tt = tv;
        }
        tot = chain_sq(v0, tt, len, NULL, &last);
        t->c2 = last;
    }
    t->cnext = e1;
    return tot;
}

static void terms_large(igea__apass *p, aptau *t, long e0, long e1)
{
    igea__ksum_add(&t->sum, large_block(p, t, e0, e1));
    t->cnt += e1 - e0;
}


/* ---- lags within the small ring ---- */

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
            if (!same) { /* W and X of the bases at the four points, their differences */
                dd w[4], x[4];
                for (int q = 0; q < 4; q++) {
                    long off = e - q * t->m - blk[q] * AP_B;
                    x[q] = *xb(p, blk[q]);
                    w[q] = off ? dd_add(*wb(p, blk[q]), dd_mul_d(x[q], (double)off)) : *wb(p, blk[q]);
                }
                A = dd_get(dd_diff3(w));
                Bc = dd_get(dd_diff3(x));
            }
            tot += same ? seg_mv0(a[0], a[1], a[2], a[3], len)
                        : seg_mv(a[0], a[1], a[2], a[3], len, A, Bc);
        } else {
            double C = 0.0;
            if (!same) {
                dd x[4];
                for (int q = 0; q < np; q++)
                    x[q] = *xb(p, blk[q]);
                C = dd_get(np == 3 ? dd_diff2(x) : dd_diff3(x));
            }
            tot += t->type == IGEA__AP_AV ? seg_av(a[0], a[1], a[2], len, C)
                                          : seg_hv(a[0], a[1], a[2], a[3], len, C);
        }
        e = end;
    }
    igea__ksum_add(&t->sum, tot);
    t->cnt += e1 - e0;
}

/* The overlapping terms in [e0, e1) of block k of a tau whose lags stay
 * within the block before: one segment of the window (one base). */
static void terms_win(igea__apass *p, aptau *t, long k, long e0, long e1)
{
    long o = e0 - k * AP_B + AP_B, m = t->m, len = e1 - e0;
    double tot;
    if (t->type == IGEA__AP_MV) {
        const double *v = p->vx + o;
        tot = seg_mv0(v, v - m, v - 2 * m, v - 3 * m, len);
    } else {
        const double *a = p->lx + o;
        tot = t->type == IGEA__AP_AV ? seg_av(a, a - m, a - 2 * m, len, 0.0)
                                     : seg_hv(a, a - m, a - 2 * m, a - 3 * m, len, 0.0);
    }
    igea__ksum_add(&t->sum, tot);
    t->cnt += e1 - e0;
}

/* One strided term from the points' local values a[] and, when they lie
 * in different blocks, the bases' part C. */
static inline double stride_term(int type, const double *a, double C)
{
    if (type == IGEA__AP_AV)
        return ((a[0] - a[1]) - (a[1] - a[2])) + C;
    double u = a[1] - a[2];
    return (((a[0] - a[1]) - u) - (u - (a[2] - a[3]))) + C;
}

/* Strided segment: the terms at a0[j st], a1[j st], ... (scalar). */
static double seg_stride(const aptau *t, const double *const *a, long cnt, long st, double C)
{
    double s0 = 0, s1 = 0;
    for (long j = 0; j < cnt; j++) {
        const long o = j * st;
        double v[4] = {a[0][o], a[1][o], a[2][o], t->type == IGEA__AP_AV ? 0.0 : a[3][o]};
        v[0] = stride_term(t->type, v, C);
        if (j & 1)
            s1 += v[0] * v[0];
        else
            s0 += v[0] * v[0];
    }
    return s0 + s1;
}

/* The strided terms (current index a multiple of m) in [e0, e1) of one
 * block (the non-overlapping Allan and Hadamard kinds), m < AP_B. */
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
            Cd = dd_add(Cd, dd_mul_d(*xb(p, b), c[q]));
            same = same && b == b0;
        }
        tot += seg_stride(t, a, cnt, m, same ? 0.0 : dd_get(Cd));
        t->cnt += cnt;
        e += cnt * m;
    }
    igea__ksum_add(&t->sum, tot);
}


/* z[j] = (a0[j m] - a1[j m]) + C (m = 1) or times 1/2 (m = 2), j < cnt. */
AP_CLONES static void means_12(const double *a0, const double *a1, long cnt, long m, double C,
                               double *z)
{
    long j = 0;
#if AP_VEC
    if (m == 1)
        for (; j + 4 <= cnt; j += 4)
            AP_STV(z + j, (AP_LD(a0 + j) - AP_LD(a1 + j)) + C);
    else /* (the odd values read: not past the last point) */
        for (; j + 5 <= cnt; j += 4) {
            const double *b0 = a0 + 2 * j, *b1 = a1 + 2 * j;
            ap_v4 u = AP_SHUF(AP_LD(b0), AP_LD(b0 + 4), 0, 2, 4, 6);
            ap_v4 v = AP_SHUF(AP_LD(b1), AP_LD(b1 + 4), 0, 2, 4, 6);
            AP_STV(z + j, ((u - v) + C) * 0.5);
        }
#endif
    for (; j < cnt; j++)
        z[j] = m == 1 ? (a0[j] - a1[j]) + C : ((a0[2 * j] - a1[2 * j]) + C) * 0.5;
}

/* z[j] = (X_e - X_{e - m}) / m for the points e = e0, e0 + m, ... < e1 of
 * one block (e0 a multiple of m, m < AP_B): at most two segments where
 * X_{e - m} stays in one block. Returns their number. */
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
            C = dd_get(dd_add(*xb(p, be), dd_neg(*xb(p, bi))));
        long cnt = (end - e + m - 1) / m;
        const double *a0 = lptr(p, e), *a1 = lptr(p, i);
        if (m <= 2)
            means_12(a0, a1, cnt, m, C, z + K);
        else if (pow2)
            for (long j = 0; j < cnt; j++)
                z[K + j] = ((a0[j * m] - a1[j * m]) + C) * inv;
        else
            for (long j = 0; j < cnt; j++)
                z[K + j] = ((a0[j * m] - a1[j * m]) + C) / (double)m;
        K += cnt;
        e += cnt * m;
    }
    return K;
}

/* The sums of K means z (z[-3] .. z[-1] hold the three before) and of
 * their products at lags 1, 2, 3: out = {sum z_i, sum z_i^2, sum z_{i-1}
 * z_i, sum z_{i-2} z_i, sum z_{i-3} z_i}, in eight lanes (i mod 8, the
 * rest in lane 0, ((0 + 1) + (2 + 3)) + ((4 + 5) + (6 + 7))). */
AP_CLONES static void acf_lags(const double *z, long K, double *out)
{
    long i = 0;
#if AP_VEC
    double r[5][8]; /* (every entry set from the vectors) */
    {
        ap_v4 S0 = {0, 0, 0, 0}, S1 = S0, Q0 = S0, Q1 = S0, A0 = S0, A1 = S0, B0 = S0, B1 = S0,
              C0 = S0, C1 = S0;
        for (; i + 8 <= K; i += 8) {
            ap_v4 a = AP_LD(z + i), b = AP_LD(z + i + 4);
            S0 += a;
            S1 += b;
            Q0 += a * a;
            Q1 += b * b;
            A0 += AP_LD(z + i - 1) * a;
            A1 += AP_LD(z + i + 3) * b;
            B0 += AP_LD(z + i - 2) * a;
            B1 += AP_LD(z + i + 2) * b;
            C0 += AP_LD(z + i - 3) * a;
            C1 += AP_LD(z + i + 1) * b;
        }
        for (int l = 0; l < 4; l++) {
            r[0][l] = S0[l], r[1][l] = Q0[l], r[2][l] = A0[l], r[3][l] = B0[l], r[4][l] = C0[l];
            r[0][4 + l] = S1[l], r[1][4 + l] = Q1[l], r[2][4 + l] = A1[l], r[3][4 + l] = B1[l];
            r[4][4 + l] = C1[l];
        }
    }
#else
    double r[5][8] = {{0}};
    for (; i + 8 <= K; i += 8)
        for (int l = 0; l < 8; l++) {
            double v = z[i + l];
            r[0][l] += v;
            r[1][l] += v * v;
            r[2][l] += z[i + l - 1] * v;
            r[3][l] += z[i + l - 2] * v;
            r[4][l] += z[i + l - 3] * v;
        }
#endif
    for (; i < K; i++) {
        double v = z[i];
        r[0][0] += v;
        r[1][0] += v * v;
        r[2][0] += z[i - 1] * v;
        r[3][0] += z[i - 2] * v;
        r[4][0] += z[i - 3] * v;
    }
    for (int q = 0; q < 5; q++)
        out[q] = ((r[q][0] + r[q][1]) + (r[q][2] + r[q][3])) +
                 ((r[q][4] + r[q][5]) + (r[q][6] + r[q][7]));
}

/* K means z (z[-3] .. z[-1] free) to the sums of tau t: the record's first
 * three one by one with the lags they have, the rest in acf_lags. */
static void means_sums(aptau *t, double *z, long K)
{
    long i = 0;
    if (K == 0)
        return;
    z[-3] = t->zc[0];
    z[-2] = t->zc[1];
    z[-1] = t->zc[2];
    for (; i < K && t->nmean + i < 3; i++) {
        long g = t->nmean + i;
        double v = z[i];
        t->zf[g] = v;
        igea__ksum_add(&t->zs[0], v);
        igea__ksum_add(&t->zs[1], v * v);
        for (long l = 1; l <= g; l++)
            igea__ksum_add(&t->zs[1 + l], z[i - l] * v);
    }
    if (i < K) {
        double o[5];
        acf_lags(z + i, K - i, o);
        for (int q = 0; q < 5; q++)
            igea__ksum_add(&t->zs[q], o[q]);
    }
    t->nmean += K;
    t->zc[0] = z[K - 3];
    t->zc[1] = z[K - 2];
    t->zc[2] = z[K - 1];
}

static void means_flush(aptau *t)
{
    means_sums(t, t->zb + 3, t->nzb);
    t->nzb = 0;
}

/* The m-sample means whose last point is in [.., e1) of block k wait in
 * t->zb; 256 or more go to the sums. */
static void means_push(igea__apass *p, aptau *t, long k, long e1)
{
    if (t->next_e >= e1)
        return;
    double *z = t->zb + 3 + t->nzb;
    long K;
    if (t->hist) { /* one mean (m >= AP_B): X_{e-m} kept when its block was current */
        long e = t->next_e;
        double C = dd_get(dd_add(*xb(p, k), dd_neg(t->hb[0])));
        double v = (lblk(p, k)[e - k * AP_B] - t->hl[0]) + C, md = (double)t->m;
        z[0] = (t->m & (t->m - 1)) == 0 ? v * (1.0 / md) : v / md;
        K = 1;
    } else {
        K = means_of(p, t->m, t->next_e, e1, z);
    }
    t->nzb += K;
    t->next_e += K * t->m;
    if (t->nzb >= 256)
        means_flush(t);
}

/* b[j] = (a[2 j] + a[2 j + 1]) / 2, j < cnt: the means of the next level. */
AP_CLONES static void halve(const double *a, long cnt, double *b)
{
    long j = 0;
#if AP_VEC
    for (; j + 4 <= cnt; j += 4) {
        /* the pairs' sums in the order 0 2 1 3 (within 128-bit halves), then
         * put in order once */
        ap_v4 lo = AP_LD(a + 2 * j), hi = AP_LD(a + 2 * j + 4);
        ap_v4 u = AP_SHUF(lo, hi, 0, 4, 2, 6) + AP_SHUF(lo, hi, 1, 5, 3, 7);
        AP_STV(b + j, AP_SHUF(u, u, 0, 2, 1, 3) * 0.5);
    }
#endif
    for (; j < cnt; j++)
        b[j] = (a[2 * j] + a[2 * j + 1]) * 0.5;
}

/* Rate data, m = 2^l < AP_B: the m-sample means of the samples of block k
 * (kB .. kB + c - 1, c = min(AP_B, n - kB): the means ending at points
 * kB + m, kB + 2m, ..., each within one block), level 0 the samples less
 * the offset, level l + 1 the pairs of level l averaged (pairwise sums,
 * halved exactly), to the sums of the taus of their level (256 or more at
 * once, fewer through t->zb; docs/stability.md). */
static void pyr_block(igea__apass *p, long k)
{
    long c = IGEA_MIN((long)AP_B, p->nraw - k * AP_B);
    int nl = p->npyr;
    if (c <= 0 || nl == 0)
        return;
    double *lv[AP_NLEV];
    long cl[AP_NLEV];
    /* block_build's samples less the offset (kB .. kB + f - 2, after its
     * d[0]; the three values before are free: d[0] and the two before it)
     * and the block's last */
    lv[0] = p->buf + 7 * AP_BUF + 4;
    if (c == AP_B)
        lv[0][AP_B - 1] = *raw_at(p, k * AP_B + AP_B - 1, 1, p->buf) - p->off;
    cl[0] = c;
    double *q = p->pz + 4;
    for (int l = 1; l < nl; l++) { /* each level after three free values, from
                                    * a multiple of 32 bytes */
        lv[l] = q;
        cl[l] = cl[l - 1] / 2;
        halve(lv[l - 1], cl[l], q);
        q += ((AP_B >> l) + 3) / 4 * 4 + 4;
    }
    for (int j = 0; j < p->ntau; j++) {
        aptau *t = &p->t[j];
        if (t->pyr < 0 || cl[t->pyr] == 0)
            continue;
        double *a = lv[t->pyr];
        long K = cl[t->pyr];
        if (t->nzb == 0 && K >= 256) {
            means_sums(t, a, K);
            continue;
        }
        memcpy(t->zb + 3 + t->nzb, a, (size_t)K * sizeof(double));
        t->nzb += K;
        if (t->nzb >= 256)
            means_flush(t);
    }
}

/* The strided term of a tau with m >= AP_B whose current point (a multiple
 * of m) is in [e0, e1) of block k, from the points kept. */
static void terms_hist(igea__apass *p, aptau *t, long k, long e0, long e1)
{
    long m = t->m, e = (e0 + m - 1) / m * m;
    int np = t->type == IGEA__AP_AV ? 3 : 4;
    if (e >= e1 || t->hn < np - 1)
        return;
    const double *c = t->type == IGEA__AP_AV ? cAV : cHV;
    double a[4] = {lblk(p, k)[e - k * AP_B], t->hl[0], t->hl[1], t->hl[2]};
    dd Cd = {0, 0};
    for (int q = 0; q < np; q++)
        Cd = dd_add(Cd, dd_mul_d(q ? t->hb[q - 1] : *xb(p, k), c[q]));
    if (t->type == IGEA__AP_AV)
        a[3] = 0.0;
    double v = stride_term(t->type, a, dd_get(Cd));
    igea__ksum_add(&t->sum, v * v);
    t->cnt++;
}

/* The point of block k (f points) at a multiple of m, kept. */
static void hist_push(igea__apass *p, aptau *t, long k, long f)
{
    long e = (k * AP_B + t->m - 1) / t->m * t->m;
    if (e >= k * AP_B + f)
        return;
    t->hb[2] = t->hb[1], t->hl[2] = t->hl[1];
    t->hb[1] = t->hb[0], t->hl[1] = t->hl[0];
    t->hb[0] = *xb(p, k), t->hl[0] = lblk(p, k)[e - k * AP_B];
    if (t->hn < 3)
        t->hn++;
}

/* The long-lag terms of the deferred blocks kd .. kd + nd - 1 (full ones),
 * tau by tau: each tau's streams read on for AP_DEFER blocks rather than
 * every long lag's at once (the same terms, added to each tau's sum in the
 * same order). */
static void large_flush(igea__apass *p)
{
    long k1 = p->kd + p->nd;
    for (int j = 0; j < p->ntau && p->nd > 0; j++) {
        aptau *t = &p->t[j];
        if (!t->large)
            continue;
        for (long b = p->kd; b < k1; b++) {
            long lo = b * AP_B, hi = lo + AP_B;
            if (lo < t->span)
                lo = t->span;
            if (lo < hi)
                terms_large(p, t, lo, hi);
        }
    }
    p->nd = 0;
}

/* The terms with current phase index in block k at offsets [x0, x1) and
 * current running-sum index (the modified kinds) at offsets [w0, w1); defer:
 * not the long lags' (large_flush takes them). */
static void block_terms(igea__apass *p, long k, long x0, long x1, long w0, long w1, int defer)
{
    long base = k * AP_B;
    for (int j = 0; j < p->ntau; j++) {
        aptau *t = &p->t[j];
        int w = t->type == IGEA__AP_MV;
        long lo = base + (w ? w0 : x0), hi = base + (w ? w1 : x1);
        if (lo < t->span)
            lo = t->span;
        if (lo < hi) {
            if (t->large) {
                if (!defer)
                    terms_large(p, t, lo, hi);
            } else if (t->win && x1 > 0) /* (not the empty block after a full
                                        * last one: no window was built for it) */
                terms_win(p, t, k, lo, hi);
            else if (t->stride || t->m == 1)
                terms_overlap(p, t, lo, hi);
            else if (t->hist)
                terms_hist(p, t, k, lo, hi);
            else
                terms_stride(p, t, lo, hi);
        }
        if (t->acf && t->pyr < 0)
            means_push(p, t, k, base + x1);
        if (t->hist)
            hist_push(p, t, k, x1);
    }
    if (p->npyr)
        pyr_block(p, k);
}

#if AP_VEC
/* The 4 x 4 transpose of rows r0 .. r3 into c0 .. c3. */
#define AP_T4(r0, r1, r2, r3, c0, c1, c2, c3)                                             \
    {                                                                                     \
        ap_v4 t0 = AP_SHUF(r0, r1, 0, 4, 2, 6), t1 = AP_SHUF(r0, r1, 1, 5, 3, 7);         \
        ap_v4 t2 = AP_SHUF(r2, r3, 0, 4, 2, 6), t3 = AP_SHUF(r2, r3, 1, 5, 3, 7);         \
        c0 = AP_SHUF(t0, t2, 0, 1, 4, 5), c1 = AP_SHUF(t1, t3, 0, 1, 4, 5);               \
        c2 = AP_SHUF(t0, t2, 2, 3, 6, 7), c3 = AP_SHUF(t1, t3, 2, 3, 6, 7);               \
    }

/* The running sums of the eight lanes of a full block (prefix2's first
 * part): lanes 0 .. 3 and 4 .. 7 side by side in two vectors, four steps
 * at a time through 4 x 4 transposes (each lane adds its values in order,
 * as the scalar loop). Returns the lanes' totals in a[8]. */
AP_CLONES static void prefix_lanes(const double *d, double *out, double *a)
{
    enum { W = AP_B / 8 };
    ap_v4 A[2] = {{0, 0, 0, 0}, {0, 0, 0, 0}};
    for (long r = 0; r < W; r += 4)
        for (int h = 0; h < 2; h++) {
            const double *s = d + 4 * h * W + r;
            double *o = out + 4 * h * W + r;
            ap_v4 c0, c1, c2, c3, o0, o1, o2, o3;
            AP_T4(AP_LD(s), AP_LD(s + W), AP_LD(s + 2 * W), AP_LD(s + 3 * W), c0, c1, c2, c3);
            o0 = A[h] += c0;
            o1 = A[h] += c1;
            o2 = A[h] += c2;
            o3 = A[h] += c3;
            AP_T4(o0, o1, o2, o3, c0, c1, c2, c3);
            AP_STV(o, c0);
            AP_STV(o + W, c1);
            AP_STV(o + 2 * W, c2);
            AP_STV(o + 3 * W, c3);
        }
    for (int l = 0; l < 4; l++)
        a[l] = A[0][l], a[4 + l] = A[1][l];
}
#endif

/* Lane l of the n values (AP_B / 8 each) offset by off[l], l >= 1. */
AP_CLONES static void lanes_off(double *out, long n, const double *off)
{
    enum { W = AP_B / 8 };
    for (int l = 1; l < 8; l++) {
        long r1 = n - l * W < W ? n - l * W : W, r = 0;
        double o = off[l], *q = out + l * W;
#if AP_VEC
        for (; r + 4 <= r1; r += 4)
            AP_STV(q + r, AP_LD(q + r) + o);
#endif
        for (; r < r1; r++)
            q[r] += o;
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
#if AP_VEC
    if (n == AP_B && d != out) {
        double a[8];
        prefix_lanes(d, out, a);
        a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6];
    } else
#endif
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
    lanes_off(out, n, off);
}

/* Block k (f points) from the raw values: its base, local values L
 * (running sums of the samples less the offset, or the points less the
 * block's first), the running sums V of L, the NaN check; and the window of
 * the short lags (the block before on this block's base, then this one). */
static void block_build(igea__apass *p, long k, long f)
{
    double *L = lblk(p, k), *bf = p->buf + 6 * AP_BUF;
    dd *X = xb(p, k);
    if (p->phase) {
        const double *x = raw_at(p, k * AP_B, f, bf);
        double x0 = x[0], c0 = 0, c1 = 0, c2 = 0, c3 = 0;
        X->hi = x0;
        X->lo = 0.0;
        long j = 0;
        for (; j + 4 <= f; j += 4) {
            c0 += x[j] * 0.0;
            c1 += x[j + 1] * 0.0;
            c2 += x[j + 2] * 0.0;
            c3 += x[j + 3] * 0.0;
        }
        for (; j < f; j++)
            c0 += x[j] * 0.0;
        if (!((c0 + c1) + (c2 + c3) == 0.0))
            p->bad = 1;
        for (j = 0; j < f; j++)
            L[j] = x[j] - x0;
    } else {
        /* point kB + j is X_{kB} + the samples kB .. kB + j - 1 (less the
         * offset); sample kB - 1 goes to the base (block 0: X_0 = 0) */
        const double *y = raw_at(p, k * AP_B - (k > 0), f, bf);
        double *d = bf + AP_BUF + 3; /* (d + 1, the samples, on a multiple of
                                      * 32 bytes: the vectors' stores and
                                      * pyr_block's loads within a line) */
        if (k > 0)
            *X = dd_add_d(dd_add_d(*xb(p, k - 1), p->llast), y[0] - p->off);
        else
            X->hi = X->lo = 0.0;
        d[0] = 0.0;
        sub_off(y + (k > 0), f - 1, p->off, d + 1);
        prefix2(d, L, f);
        if (!(isfinite(L[f - 1]) && isfinite(X->hi)))
            p->bad = 1; /* a NaN or infinity spreads to the block's last sum */
    }
    double dX = k > 0 ? dd_get(dd_add(*X, dd_neg(*xb(p, k - 1)))) : 0.0;
    if (p->lx) { /* X - X_{kB}: the block before (L - dX), then this block */
        if (k > 0)
            shift_add(lblk(p, k - 1), AP_B, 0.0, -dX, p->lx);
        memcpy(p->lx + AP_B, L, (size_t)f * sizeof(double));
    }
    p->llast = L[f - 1];
    if (p->need_w) {
        double *V = p->rsv ? vblk(p, k) : p->vbuf;
        dd *W = wb(p, k);
        if (k > 0)
            *W = dd_add_d(dd_add(*wb(p, k - 1), dd_mul_d(*xb(p, k - 1), (double)AP_B)), p->vlast);
        else
            W->hi = W->lo = 0.0;
        V[0] = 0.0;
        prefix2(L, V + 1, f);
        if (p->vx) { /* W_t - W_{kB} - (t - kB) X_{kB}: the block before
                      * ((V_j - vlast) + (B - j) dX), then this block */
            if (k > 0)
                vx_prev(vblk(p, k - 1), p->vlast, dX, p->vx);
            memcpy(p->vx + AP_B, V, (size_t)(f + 1) * sizeof(double));
        }
        p->vlast = V[f];
    }
}

/* Room in the ring of bases for block k. */
static int base_room(igea__apass *p, long k)
{
    if (k < p->cap || p->cap >= p->cap_max)
        return 0;
    long nc = p->cap + p->cap / 2 + 1; /* 1.5 x: at most a third unused */
    return base_grow(p, nc > p->cap_max ? p->cap_max : nc);
}

/* Block k (f points) built and its terms computed; the last block of the
 * record (f <= AP_B) also gives the running sum's last index N. */
static int block_do(igea__apass *p, long k, long f, int last)
{
    int st = base_room(p, k);
    if (st)
        return st;
    block_build(p, k, f);
    p->k = k + 1;
    if (!last) {
        int defer = AP_DEFER > 1 && p->nlarge > 0;
        block_terms(p, k, 0, f, 0, f, defer);
        if (defer) {
            if (p->nd++ == 0)
                p->kd = k;
            if (p->nd == AP_DEFER)
                large_flush(p);
        }
        return 0;
    }
    large_flush(p);
    if (f < AP_B || !p->need_w) {
        block_terms(p, k, 0, f, 0, f < AP_B ? f + 1 : f, 0);
        return 0;
    }
    /* a full last block: W_N is the first running sum of an empty block */
    block_terms(p, k, 0, AP_B, 0, AP_B, 0);
    if ((st = base_room(p, k + 1)))
        return st;
    dd *X = xb(p, k + 1), *W = wb(p, k + 1);
    X->hi = X->lo = 0.0;
    *W = dd_add_d(dd_add(*wb(p, k), dd_mul_d(*xb(p, k), (double)AP_B)), p->vlast);
    if (p->rsv)
        *vptr(p, (k + 1) * AP_B) = 0.0;
    p->k = k + 2;
    block_terms(p, k + 1, 0, 0, 0, 1, 0);
    return 0;
}

/* Rate data: the offset, the mean of the first min(n, AP_B) samples. */
static void rate_offset(igea__apass *p, const double *v, long n)
{
    igea__ksum k = {0, 0};
    for (long i = 0; i < n; i++)
        igea__ksum_add(&k, v[i]);
    p->off = n ? igea__ksum_get(&k) / (double)n : 0.0;
    p->have_off = 1;
}

/* Every block complete in the values received (not the last one). */
static int blocks_ready(igea__apass *p)
{
    if (!p->phase && !p->have_off)
        return 0;
    while (p->N > (p->k + 1) * AP_B) { /* a value past the block: not the last */
        int st = block_do(p, p->k, AP_B, 0);
        if (st)
            return st;
    }
    return 0;
}

int igea__apass_feed(igea__apass *p, long n, const double *v)
{
    if (p->ended)
        return -1;
    long i = 0;
    while (i < n) {
        /* raw values from the oldest a block's terms read on stay */
        long keep = p->k * AP_B - p->reach - (p->phase ? 0 : 1), R = p->rawcap * AP_B;
        if (p->src && p->rawcap >= p->rawcap_max) /* older values are read back: the */
            keep = p->k * AP_B - (AP_DEFER + 2) * AP_B; /* deferred blocks and one before stay */
        if (keep < 0)
            keep = 0;
        long room = keep + R - p->nraw;
        if (room < AP_B && p->rawcap < p->rawcap_max) {
            long nc = p->rawcap + p->rawcap / 2 + 1;
            if (raw_grow(p, nc > p->rawcap_max ? p->rawcap_max : nc))
                return IGEA_ENOMEM;
            continue;
        }
        long take = IGEA_MIN(n - i, IGEA_MIN(room, (long)AP_B));
        long s = mod_l(p->nraw, R), c1 = IGEA_MIN(take, R - s);
        memcpy(p->raw + s, v + i, (size_t)c1 * sizeof(double));
        memcpy(p->raw, v + i + c1, (size_t)(take - c1) * sizeof(double));
        if (p->src)
            src_fed(p->src, p->nraw, v + i, take);
        p->nraw += take;
        i += take;
        p->N = p->phase ? p->nraw : p->nraw + 1;
        if (!p->phase && !p->have_off && p->nraw >= AP_B)
            rate_offset(p, raw_at(p, 0, AP_B, p->buf), AP_B);
        int st = blocks_ready(p);
        if (!st && p->src)
            st = p->src->err;
        if (st)
            return st;
    }
    return 0;
}

static void acf_end(igea__apass *p)
{
    for (int j = 0; j < p->ntau; j++)
        if (p->t[j].acf)
            means_flush(&p->t[j]);
}

int igea__apass_end(igea__apass *p)
{
    if (p->ended)
        return 0;
    p->ended = 1;
    if (p->nraw == 0)
        return 0;
    if (!p->phase && !p->have_off)
        rate_offset(p, raw_at(p, 0, p->nraw, p->buf), p->nraw);
    int st = blocks_ready(p);
    if (!st && p->N > p->k * AP_B)
        st = block_do(p, p->k, p->N - p->k * AP_B, 1);
    acf_end(p);
    if (!st && p->src)
        st = p->src->err;
    return st;
}

int igea__apass_whole(int phase, int ntau, const igea__aptau_spec *spec, long n,
                      const double *v, igea__apass **out)
{
    igea__apass *p = NULL;
    long N = phase ? n : n + 1;
    int st = apass_alloc(phase, ntau, spec, v, n, N, &p);
    if (st)
        return st;
    p->nraw = n;
    p->N = N;
    p->ended = 1;
    if (!phase)
        rate_offset(p, v, IGEA_MIN(n, (long)AP_B));
    for (long k = 0; !st && k * AP_B < N; k++)
        st = block_do(p, k, IGEA_MIN((long)AP_B, N - k * AP_B), (k + 1) * AP_B >= N);
    acf_end(p);
    if (st) {
        igea__apass_free(p);
        return st;
    }
    *out = p;
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
static double apacf_r1(const igea__apacf *a, double tol)
{
    double N = a->n, s = igea__ksum_get(&a->s), zb = s / N;
    double den = igea__ksum_get(&a->ss) - N * zb * zb;
    double num = igea__ksum_get(&a->lag) - zb * (s - a->last) - zb * (s - a->first) +
                 (N - 1) * zb * zb;
    return den > tol ? num / den : 0.0;
}

int igea__apass_alpha(const igea__apass *p, int j)
{
    const aptau *t = &p->t[j];
    if (!t->acf || t->nmean < 32)
        return IGEA_STABILITY_NOISE_AUTO;
    /* the means z_0 .. z_{K-1} (Q = sum z^2, L_l = sum z_{i-l} z_i), their
     * first differences d_j = z_j - z_{j-1} (j = 1 .. K-1: D = sum d^2, M_l =
     * sum d_{j-l} d_j) and second differences e_j = d_j - d_{j-1}, each
     * series' sums from the lag sums of the one before and its end values
     * (docs/stability.md, "One pass") */
    double K = (double)t->nmean, Q = igea__ksum_get(&t->zs[1]);
    double L1 = igea__ksum_get(&t->zs[2]), L2 = igea__ksum_get(&t->zs[3]);
    double L3 = igea__ksum_get(&t->zs[4]);
    double z0 = t->zf[0], z1 = t->zf[1], z2 = t->zf[2];
    double y3 = t->zc[0], y2 = t->zc[1], y1 = t->zc[2]; /* z_{K-3}, z_{K-2}, z_{K-1} */
    double D = 2.0 * Q - z0 * z0 - y1 * y1 - 2.0 * L1;
    double M1 = 2.0 * L1 - z0 * z1 - y2 * y1 - Q + z0 * z0 + y1 * y1 - L2;
    double M2 = (L2 - z0 * z2) - (L1 - z0 * z1 - y2 * y1) - L3 + (L2 - y3 * y1);
    double w1 = z1 - z0, w2 = z2 - z1, wk1 = y2 - y3, wk = y1 - y2;
    igea__apacf a[3] = {{0}};
    a[0].n = K;
    igea__ksum_add(&a[0].s, igea__ksum_get(&t->zs[0]));
    igea__ksum_add(&a[0].ss, Q);
    igea__ksum_add(&a[0].lag, L1);
    a[0].first = z0;
    a[0].last = y1;
    a[1].n = K - 1.0;
    igea__ksum_add(&a[1].s, y1 - z0);
    igea__ksum_add(&a[1].ss, D);
    igea__ksum_add(&a[1].lag, M1);
    a[1].first = w1;
    a[1].last = wk;
    a[2].n = K - 2.0;
    igea__ksum_add(&a[2].s, wk - w1);
    igea__ksum_add(&a[2].ss, 2.0 * D - w1 * w1 - wk * wk - 2.0 * M1);
    igea__ksum_add(&a[2].lag, 2.0 * M1 - w1 * w2 - wk1 * wk - D + w1 * w1 + wk * wk - M2);
    a[2].first = w2 - w1;
    a[2].last = wk - wk1;
    /* the rounding of a derived series' sums: a series whose spread is
     * below it is constant (r1 = 0) [D] */
    double tol = 1e-12 * Q;
    for (int d = 0; d <= 2; d++) {
        double r1 = apacf_r1(&a[d], tol), delta = r1 / (1.0 + r1);
        if (delta < 0.25 || d == 2) {
            long alpha = lround(-2.0 * (delta + d));
            return (int)IGEA_MAX(IGEA_STABILITY_NOISE_RWFM, IGEA_MIN(IGEA_STABILITY_NOISE_WPM, alpha));
        }
        tol *= 4.0;
    }
    return IGEA_STABILITY_NOISE_WFM;
}
