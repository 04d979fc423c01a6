/* stability_stream.c - the Allan and Hadamard deviations of a record given
 * in pieces (igea_stability_stream_*): the one pass of stability_pass.c
 * fed as the pieces come, the block statistic's means kept, the results
 * those of igea_stability_allan / igea_stability_dev on the whole record. */
#include "igea/stability.h"
#include "internal.h"
#include "stability_internal.h"

#define MAX_OPEN 32 /* averaging factors of an open spacing: m < 2^31 */

struct igea_stability_stream {
    int kind, data_type, noise, rate, given;
    double fs, conf;
    int ntau;
    double *tau;          /* the given taus (ntau of them) */
    long *m;              /* their factors */
    igea__apass *p;
    double nfed;          /* samples fed */
    int failed;           /* 0, or the status that made it unusable (IGEA_ENOMEM:
                           * the ring could not grow; IGEA_EREAD: a value read back) */
    int ended;            /* the results were asked for */
    long nb;              /* block statistic: samples per block (0: none) */
    igea__ksum cur;       /* the current block's sum */
    long inblk;
    double *means;
    long nmeans, capmeans;
};

static int rate_kind(int k) { return k >= IGEA_STABILITY_ALLAN_OVERLAPPING && k <= IGEA_STABILITY_ALLAN_NONOVERLAPPING; }

static int pass_kind(int k) { return k >= IGEA_STABILITY_ALLAN_ADEV && k <= IGEA_STABILITY_ALLAN_OHDEV; }

/* Next factor of a spacing (igea_stability_taus's sequence). */
static long next_m(long m, int spacing)
{
    if (spacing == IGEA_STABILITY_TAUS_OCTAVE)
        return 2 * m;
    long p = 1;
    while (p * 10 <= m)
        p *= 10;
    long lead = m / p;
    return lead == 1 ? 2 * p : lead == 2 ? 4 * p : 10 * p;
}

void igea_stability_stream_free(igea_stability_stream *h)
{
    if (!h)
        return;
    igea__apass_free(h->p);
    free(h->tau);
    free(h->m);
    free(h->means);
    free(h);
}

int igea_stability_stream_create(double fs, int data_type, int kind, int noise, double conf,
                                 int ntau, const double *tau, int spacing, double block,
                                 igea_stability_stream **out)
{
    if (out)
        *out = NULL;
    if (!(isfinite(fs) && fs > 0.0))
        return -1;
    if (data_type != IGEA_STABILITY_DATA_FREQ && data_type != IGEA_STABILITY_DATA_PHASE)
        return -2;
    if (!rate_kind(kind) && !pass_kind(kind))
        return -3;
    if (rate_kind(kind) && data_type != IGEA_STABILITY_DATA_FREQ)
        return -2;
    if (!((noise == IGEA_STABILITY_NOISE_AUTO && rate_kind(kind)) ||
          (noise >= IGEA_STABILITY_NOISE_RWFM && noise <= IGEA_STABILITY_NOISE_WPM)))
        return -4;
    if (!(conf > 0.0 && conf < 1.0))
        return -5;
    if (ntau < 0)
        return -6;
    if (ntau > 0 && !tau)
        return -7;
    for (int j = 0; j < ntau; j++) {
        double v = tau[j] * fs;
        if (!(isfinite(tau[j]) && tau[j] > 0.0 && v >= 0.5 && v < 2147483648.0))
            return -7;
    }
    if (spacing != IGEA_STABILITY_TAUS_OCTAVE && spacing != IGEA_STABILITY_TAUS_DECADE)
        return -8;
    double nbv = block * fs;
    if (!(isfinite(block) && block >= 0.0) || (block > 0.0 && !(nbv >= 0.5 && nbv < 2147483648.0)))
        return -9;
    if (!out)
        return -10;
    igea_stability_stream *h = calloc(1, sizeof *h);
    if (!h)
        return IGEA_ENOMEM;
    h->kind = kind;
    h->data_type = data_type;
    h->noise = noise;
    h->rate = rate_kind(kind);
    h->given = ntau > 0;
    h->fs = fs;
    h->conf = conf;
    h->nb = block > 0.0 ? lround(nbv) : 0;
    if (!h->rate && ntau == 0 && spacing == IGEA_STABILITY_TAUS_DECADE) {
        h->ntau = 0;
        for (long m = 1; m < 2147483648L && h->ntau < MAX_OPEN; m = next_m(m, spacing))
            h->ntau++;
    } else {
        h->ntau = ntau > 0 ? ntau : MAX_OPEN - 1; /* octaves 1 .. 2^30 */
    }
    h->tau = igea__dalloc((size_t)h->ntau);
    h->m = malloc((size_t)h->ntau * sizeof(long));
    igea__aptau_spec *sp = malloc((size_t)h->ntau * sizeof *sp);
    int st = h->tau && h->m && sp ? 0 : IGEA_ENOMEM;
    long m = 1;
    for (int j = 0; j < h->ntau && !st; j++) {
        if (ntau > 0) {
            h->m[j] = lround(tau[j] * fs);
        } else {
            h->m[j] = m;
            m = h->rate ? 2 * m : next_m(m, spacing);
        }
        h->tau[j] = (double)h->m[j] / fs;
        igea__stability_pass_spec(kind, h->m[j], h->rate && noise == IGEA_STABILITY_NOISE_AUTO,
                                  &sp[j]);
    }
    if (!st)
        st = igea__apass_new(data_type == IGEA_STABILITY_DATA_PHASE, h->ntau, sp, 0, &h->p);
    free(sp);
    if (st) {
        igea_stability_stream_free(h);
        return st;
    }
    *out = h;
    return 0;
}

int igea_stability_stream_feed(igea_stability_stream *h, int n, const double *v)
{
    if (!h)
        return -1;
    if (n < 0)
        return -2;
    if (n > 0 && !v)
        return -3;
    if (h->failed)
        return h->failed;
    if (h->ended)
        return IGEA_EEMPTY;
    if (!igea__finite_vec(n, v, 1))
        return IGEA_ENONFINITE; /* nothing fed */
    if (h->nb > 0) { /* the block means (igea_stability_block's sums) */
        for (int i = 0; i < n; i++) {
            igea__ksum_add(&h->cur, v[i]);
            if (++h->inblk == h->nb) {
                if (h->nmeans == h->capmeans) {
                    long nc = h->capmeans ? 2 * h->capmeans : 64;
                    double *nm = realloc(h->means, (size_t)nc * sizeof(double));
                    if (!nm) {
                        h->failed = IGEA_ENOMEM;
                        return IGEA_ENOMEM;
                    }
                    h->means = nm;
                    h->capmeans = nc;
                }
                h->means[h->nmeans++] = igea__ksum_get(&h->cur) / (double)h->nb;
                h->cur.s = h->cur.c = 0.0;
                h->inblk = 0;
            }
        }
    }
    int st = igea__apass_feed(h->p, n, v);
    if (st) {
        h->failed = st == IGEA_EREAD ? IGEA_EREAD : IGEA_ENOMEM;
        return h->failed;
    }
    h->nfed += (double)n;
    return 0;
}

/* igea_stability_stream_source with a ring of ring blocks (the tests' short
 * records reach past a small one). */
int igea__stability_stream_source_ring(igea_stability_stream *h, int fd, double offset,
                                       int stride, long ring)
{
    if (!h || h->nfed > 0 || h->ended || h->failed)
        return -1;
    if (fd < 0)
        return -2;
    if (!(offset >= 0 && offset <= 9007199254740992.0 && offset == floor(offset)))
        return -3;
    if (stride < (int)sizeof(double) || stride > (1 << 17))
        return -4;
    return igea__apass_source(h->p, fd, offset, stride, ring);
}

int igea_stability_stream_source(igea_stability_stream *h, int fd, double offset, int stride)
{
    return igea__stability_stream_source_ring(h, fd, offset, stride, IGEA__AP_SRC_RING);
}

int igea_stability_stream_samples(const igea_stability_stream *h, double *n)
{
    if (!h)
        return -1;
    if (!n)
        return -2;
    *n = h->nfed;
    return 0;
}

int igea_stability_stream_result(igea_stability_stream *h, int ntau_max, int *ntau,
                                 double *tau, double *dev, double *lo, double *hi, double *edf,
                                 int *alpha, int *count, double *block)
{
    if (!h)
        return -1;
    if (ntau_max < 1)
        return -2;
    if (!ntau)
        return -3;
    if (!tau)
        return -4;
    if (!dev)
        return -5;
    if (h->failed)
        return h->failed;
    if (h->nfed < 2.0 || h->nfed > 2147483647.0)
        return IGEA_EEMPTY;
    igea__apass *p = h->p;
    int st = igea__apass_end(p); /* the record ends here (again: no change) */
    h->ended = 1;
    if (!st && igea__apass_nonfinite(p))
        st = IGEA_ENONFINITE;
    int n = (int)h->nfed, k = 0, K = h->ntau;
    double *w = igea__dalloc(5 * (size_t)K);
    int *iw = igea__ialloc(3 * (size_t)K);
    if (!st && (!w || !iw))
        st = IGEA_ENOMEM;
    double *t = w, *d = t + K, *l = d + K, *hh = l + K, *e = hh + K;
    int *al = iw, *cw = al + K, *idx = cw + K;
    for (int j = 0; j < K && !st; j++) {
        double ss;
        long cnt;
        igea__apass_get(p, j, &ss, &cnt);
        if (cnt < 1) {
            if (h->given)
                st = IGEA_EEMPTY; /* a given tau longer than the record allows */
            continue;
        }
        idx[k] = j;
        t[k] = h->tau[j];
        d[k] = igea__stability_pass_dev(h->kind, h->data_type == IGEA_STABILITY_DATA_PHASE, h->fs,
                                        h->m[j], ss, cnt);
        cw[k] = (int)cnt;
        al[k] = h->noise == IGEA_STABILITY_NOISE_AUTO ? igea__apass_alpha(p, j) : h->noise;
        k++;
    }
    if (!st && k > ntau_max)
        st = IGEA_EEMPTY;
    if (!st && k == 0)
        st = IGEA_EEMPTY;
    if (!st && h->rate) {
        st = igea__stability_allan_intervals(n, h->fs, k, t, h->kind, h->noise, h->conf, al, d, l,
                                             hh, e);
        if (!st && h->noise == IGEA_STABILITY_NOISE_AUTO) /* the type the EDF used */
            for (int j = 0, last = IGEA_STABILITY_NOISE_WFM; j < k; j++) {
                if (al[j] == IGEA_STABILITY_NOISE_AUTO)
                    al[j] = last;
                last = al[j];
            }
    } else if (!st) {
        double N = h->data_type == IGEA_STABILITY_DATA_PHASE ? (double)n : (double)n + 1.0;
        for (int j = 0; j < k && !st; j++)
            if (igea__edf_interval(d[j], igea__stability_dev_edf(h->kind, al[j], N, (double)h->m[idx[j]]),
                                   h->conf, &l[j], &hh[j], &e[j]))
                st = IGEA_ENOCONV;
    }
    for (int j = 0; j < k && !st; j++)
        if (!isfinite(d[j]))
            st = IGEA_ENOCONV;
    double bo[IGEA_STABILITY_BLOCK_LEN];
    if (!st && block) {
        if (h->nmeans >= 2 && h->nb <= n) {
            igea__stability_block_stats(h->nmeans, h->means, h->nb, bo);
        } else {
            for (int i = 0; i < IGEA_STABILITY_BLOCK_LEN; i++)
                bo[i] = NAN;
            bo[IGEA_STABILITY_BLOCK_NBLOCK] = (double)(h->nb > 0 ? h->nmeans : 0);
        }
    }
    if (!st) {
        size_t sz = (size_t)k * sizeof(double);
        *ntau = k;
        memcpy(tau, t, sz);
        memcpy(dev, d, sz);
        if (lo)
            memcpy(lo, l, sz);
        if (hi)
            memcpy(hi, hh, sz);
        if (edf)
            memcpy(edf, e, sz);
        if (alpha)
            memcpy(alpha, al, (size_t)k * sizeof(int));
        if (count)
            memcpy(count, cw, (size_t)k * sizeof(int));
        if (block)
            memcpy(block, bo, sizeof bo);
    }
    free(w);
    free(iw);
    return st;
}
