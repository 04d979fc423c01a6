/* src/cli/svg.c - self-contained SVG pictures for --plot FILE.svg: panels
 * with linear or log10 axes, series, markers, error bars, bands, marker
 * lines and legends; the plots of the commands. Only presentation: every
 * number drawn is one a command already computed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                      "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"};
#define NPAL ((int)(sizeof palette / sizeof palette[0]))
static const char *col(int c) { return palette[((c % NPAL) + NPAL) % NPAL]; }

enum { LEG_LINE, LEG_POINT, LEG_BAND, LEG_DASH, LEG_BAR };

/* Length of the valid UTF-8 sequence at p (0: invalid). */
static int utf8_len(const unsigned char *p)
{
    int n = p[0] >= 0xF0 && p[0] <= 0xF4 ? 4 : p[0] >= 0xE0 ? 3 : p[0] >= 0xC2 && p[0] < 0xE0 ? 2 : 0;
    for (int k = 1; k < n; k++)
        if ((p[k] & 0xC0) != 0x80)
            return 0;
    return n;
}

static void put_escaped(FILE *f, const char *text)
{
    const unsigned char *p = (const unsigned char *)(text ? text : "");
    while (*p) {
        int n;
        if (*p == '&')
            fputs("&amp;", f);
        else if (*p == '<')
            fputs("&lt;", f);
        else if (*p == '>')
            fputs("&gt;", f);
        else if (*p == '"')
            fputs("&quot;", f);
        else if (*p == '\'')
            fputs("&apos;", f);
        else if (*p < 0x80)
            fputc(*p < 0x20 && *p != '\t' && *p != '\n' ? '?' : *p, f);
        else if ((n = utf8_len(p)) > 0) {
            fwrite(p, 1, (size_t)n, f);
            p += n;
            continue;
        } else
            fputc('?', f);
        p++;
    }
}

void cli_svg_text(cli_svg *s, double x, double y, const char *anchor, const char *text)
{
    fprintf(s->f, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"%s\">", x, y, anchor);
    put_escaped(s->f, text);
    fputs("</text>\n", s->f);
}

void cli_svg_begin(cli_svg *s, FILE *f, double width, double height, const char *title)
{
    memset(s, 0, sizeof *s);
    s->f = f;
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"%.0f\" "
               "height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" "
               "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            width, height, width, height);
    if (title) {
        fputs("<title>", f);
        put_escaped(f, title);
        fputs("</title>\n", f);
    }
}

/* Characters of a label (UTF-8 lead bytes). */
static double label_chars(const char *label)
{
    size_t c = 0;
    for (const unsigned char *p = (const unsigned char *)label; *p; p++)
        c += (*p & 0xC0) != 0x80;
    return (double)c;
}

/* The width of legend entry k laid out in a row, its gap included: the
 * symbol, the text at 7 px a character (a generous mean width at 12 px
 * sans) and 14 px to the next entry. */
static double row_entry_width(const char *label) { return 32 + 7.0 * label_chars(label) + 14; }

/* The rows of a row legend of n labels no wider than maxw: for each entry
 * its row and its offset in the row; returns the rows, *w the widest. */
static int row_layout(const char *const *label, int n, double maxw, int *row, double *off,
                      double *w)
{
    int rows = n > 0;
    double x = 0;
    *w = 0;
    for (int k = 0; k < n; k++) {
        double ew = row_entry_width(label[k]);
        if (x > 0 && x + ew - 14 > maxw)
            rows++, x = 0;
        row[k] = rows - 1, off[k] = x;
        x += ew;
        *w = x - 14 > *w ? x - 14 : *w;
    }
    return rows;
}

/* The height of the row legend of these labels in a plot area pw wide. */
static double row_legend_height(const char *const *label, int n, double pw)
{
    int row[CLI_SVG_LEGEND_MAX];
    double off[CLI_SVG_LEGEND_MAX], w;
    return 8 + 16.0 * row_layout(label, n < CLI_SVG_LEGEND_MAX ? n : CLI_SVG_LEGEND_MAX,
                                 pw - 20, row, off, &w);
}

static void legend(cli_svg *s)
{
    if (!s->panel || !s->nleg)
        return;
    double w, h, ex[CLI_SVG_LEGEND_MAX], ey[CLI_SVG_LEGEND_MAX];
    if (s->legrow) {
        int row[CLI_SVG_LEGEND_MAX];
        double off[CLI_SVG_LEGEND_MAX];
        int rows = row_layout(s->leg, s->nleg, s->pw - 20, row, off, &w);
        w += 8, h = 8 + 16.0 * rows;
        for (int k = 0; k < s->nleg; k++)
            ex[k] = off[k], ey[k] = 14 + 16.0 * row[k];
    } else {
        /* wide enough for the longest label, at most the panel's width */
        double chars = 0;
        for (int k = 0; k < s->nleg; k++)
            chars = label_chars(s->leg[k]) > chars ? label_chars(s->leg[k]) : chars;
        w = 40 + 7.0 * chars, h = 8 + 16.0 * s->nleg;
        w = w < 120 ? 120 : w > s->pw - 12 ? s->pw - 12 : w;
        for (int k = 0; k < s->nleg; k++)
            ex[k] = 0, ey[k] = 14 + 16.0 * k;
    }
    double x = s->px + s->pw - w - 6, y = s->legbottom ? s->py + s->ph - h - 6 : s->py + 6;
    fprintf(s->f, "<g class=\"legend\">\n<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" "
                  "height=\"%.2f\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999\"/>\n",
            x, y, w, h);
    for (int k = 0; k < s->nleg; k++) {
        double lx = x + ex[k], ly = y + ey[k];
        const char *c = col(s->legcolor[k]);
        if (s->legkind[k] == LEG_POINT)
            fprintf(s->f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"3\" fill=\"%s\"/>\n", lx + 16, ly - 4, c);
        else if (s->legkind[k] == LEG_BAND || s->legkind[k] == LEG_BAR)
            fprintf(s->f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"20\" height=\"8\" fill=\"%s\" "
                          "fill-opacity=\"%s\"/>\n", lx + 6, ly - 8, c,
                    s->legkind[k] == LEG_BAND ? "0.25" : "1");
        else
            fprintf(s->f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\" "
                          "stroke-width=\"1.5\"%s/>\n", lx + 6, ly - 4, lx + 26, ly - 4, c,
                    s->legkind[k] == LEG_DASH ? " stroke-dasharray=\"5,3\"" : "");
        cli_svg_text(s, lx + 32, ly, "start", s->leg[k]);
    }
    fputs("</g>\n", s->f);
    s->nleg = 0;
}

void cli_svg_end(cli_svg *s)
{
    legend(s);
    if (s->panel)
        fputs("</g>\n", s->f);
    s->panel = 0;
    fputs("</svg>\n", s->f);
}

void cli_svg_range(cli_svg_axis *ax, const double *v, long n, long stride)
{
    for (long i = 0; v && i < n; i++) {
        double x = v[i * stride];
        if (!isfinite(x) || (ax->log && !(x > 0)))
            continue;
        if (x < ax->lo)
            ax->lo = x;
        if (x > ax->hi)
            ax->hi = x;
    }
}

/* The axis range in plotting units (log10 on a log axis), never empty. */
static void plot_range(const cli_svg_axis *ax, double *a, double *b)
{
    double lo = ax->lo, hi = ax->hi;
    if (ax->log) {
        if (!(lo > 0 && lo <= hi && isfinite(hi)))
            lo = 1, hi = 10;
        lo = log10(lo), hi = log10(hi);
        if (hi - lo < 1e-9)
            lo -= 0.5, hi += 0.5;
        double pad = 0.04 * (hi - lo);
        lo -= pad, hi += pad;
    } else {
        if (!(lo <= hi && isfinite(lo) && isfinite(hi)))
            lo = 0, hi = 1;
        if (hi - lo <= 1e-12 * (fabs(lo) + fabs(hi)) || hi == lo) {
            double d = lo == 0 ? 1 : 0.5 * fabs(lo);
            lo -= d, hi += d;
        }
        double pad = 0.04 * (hi - lo);
        lo -= pad, hi += pad;
    }
    *a = lo, *b = hi;
}

/* Pixel of a data value; 0 when it cannot be drawn. */
static int map_x(const cli_svg *s, double v, double *px)
{
    if (!isfinite(v) || (s->xlog && !(v > 0)))
        return 0;
    double u = s->xlog ? log10(v) : v;
    *px = s->px + (u - s->x0) / (s->x1 - s->x0) * s->pw;
    return isfinite(*px) && fabs(*px) < 1e7;
}

static int map_y(const cli_svg *s, double v, double *py)
{
    if (!isfinite(v) || (s->ylog && !(v > 0)))
        return 0;
    double u = s->ylog ? log10(v) : v;
    *py = s->py + s->ph - (u - s->y0) / (s->y1 - s->y0) * s->ph;
    return isfinite(*py) && fabs(*py) < 1e7;
}

/* Tick values in plotting units between a and b (at most max). */
static int ticks(double a, double b, int log, int integer, double *t, int max)
{
    int n = 0;
    if (log && b - a >= 1.5) {
        double step = ceil((b - a) / 8);
        for (double k = ceil(a / step) * step; k <= b && n < max; k += step)
            t[n++] = k;
        return n;
    }
    if (log) { /* mantissas 1, 2, 5 */
        static const double m[3] = {1, 2, 5};
        for (double d = floor(a); d <= b && n < max; d++)
            for (int k = 0; k < 3 && n < max; k++) {
                double u = d + log10(m[k]);
                if (u >= a && u <= b)
                    t[n++] = u;
            }
        return n;
    }
    double raw = (b - a) / 6, p = pow(10, floor(log10(raw))), r = raw / p;
    double step = (r < 1.5 ? 1 : r < 3.5 ? 2 : r < 7.5 ? 5 : 10) * p;
    if (integer && step < 1)
        step = 1;
    for (double k = ceil(a / step); k * step <= b && n < max; k++)
        t[n++] = fabs(k * step) < 1e-9 * step ? 0 : k * step;
    return n;
}

static void tick_label(char *buf, size_t size, double u, int log)
{
    snprintf(buf, size, "%.4g", log ? pow(10, u) : u);
}

/* Ticks, tick labels and grid of one axis (vertical: the y axis). */
static void axis_ticks(cli_svg *s, int vertical)
{
    double t[40], a = vertical ? s->y0 : s->x0, b = vertical ? s->y1 : s->x1;
    int log = vertical ? s->ylog : s->xlog;
    if (vertical ? s->ynoticks : s->xnoticks)
        return;
    int n = ticks(a, b, log, vertical ? s->yint : s->xint, t, 40);
    char buf[32];
    for (int k = 0; k < n; k++) {
        double p = vertical ? s->py + s->ph - (t[k] - a) / (b - a) * s->ph
                            : s->px + (t[k] - a) / (b - a) * s->pw;
        tick_label(buf, sizeof buf, t[k], log);
        if (vertical) {
            fprintf(s->f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#ddd\"/>\n"
                          "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
                          "stroke=\"black\"/>\n",
                    s->px, p, s->px + s->pw, p, s->px - 5, p, s->px, p);
            cli_svg_text(s, s->px - 8, p + 4, "end", buf);
        } else {
            fprintf(s->f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#ddd\"/>\n"
                          "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
                          "stroke=\"black\"/>\n",
                    p, s->py, p, s->py + s->ph, p, s->py + s->ph, p, s->py + s->ph + 5);
            cli_svg_text(s, p, s->py + s->ph + 18, "middle", buf);
        }
    }
}

void cli_svg_panel(cli_svg *s, double left, double top, double width, double height,
                   const cli_svg_axis *x, const cli_svg_axis *y, const char *title)
{
    legend(s);
    if (s->panel)
        fputs("</g>\n", s->f);
    s->panel++;
    s->px = left + 70, s->py = top + 28, s->pw = width - 90, s->ph = height - 72;
    s->xlog = x->log, s->ylog = y->log;
    s->xint = x->integer, s->yint = y->integer;
    s->xnoticks = x->noticks, s->ynoticks = y->noticks;
    s->legrow = s->legbottom = 0;
    plot_range(x, &s->x0, &s->x1);
    plot_range(y, &s->y0, &s->y1);
    fprintf(s->f, "<g class=\"axes\" id=\"axes%d\" data-xlog=\"%d\" data-ylog=\"%d\">\n"
                  "<clipPath id=\"clip%d\"><rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" "
                  "height=\"%.2f\"/></clipPath>\n",
            s->panel, s->xlog, s->ylog, s->panel, s->px, s->py, s->pw, s->ph);
    axis_ticks(s, 0);
    axis_ticks(s, 1);
    fprintf(s->f, "<rect class=\"frame\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" "
                  "fill=\"none\" stroke=\"black\"/>\n", s->px, s->py, s->pw, s->ph);
    cli_svg_text(s, s->px + s->pw / 2, s->py + s->ph + 38, "middle", x->label);
    fprintf(s->f, "<g transform=\"translate(%.2f %.2f) rotate(-90)\">", left + 16,
            s->py + s->ph / 2);
    cli_svg_text(s, 0, 0, "middle", y->label);
    fputs("</g>\n", s->f);
    if (title)
        cli_svg_text(s, s->px + s->pw / 2, top + 18, "middle", title);
}

static void add_legend(cli_svg *s, const char *label, int color, int kind)
{
    if (!label || s->nleg >= CLI_SVG_LEGEND_MAX)
        return;
    s->leg[s->nleg] = label, s->legcolor[s->nleg] = color, s->legkind[s->nleg] = kind;
    s->nleg++;
}

static double xval(const double *x, long xs, long i) { return x ? x[i * xs] : (double)i; }

void cli_svg_line(cli_svg *s, const double *x, long xs, const double *y, long ys, long n,
                  int color, const char *label)
{
    long drawn = 0;
    double px, py;
    for (long i = 0; y && i < n; i++) {
        if (!map_x(s, xval(x, xs, i), &px) || !map_y(s, y[i * ys], &py))
            continue;
        if (!drawn++)
            fprintf(s->f, "<polyline class=\"series\" clip-path=\"url(#clip%d)\" fill=\"none\" "
                          "stroke=\"%s\" stroke-width=\"1.2\" points=\"", s->panel, col(color));
        fprintf(s->f, "%s%.2f,%.2f", drawn > 1 ? " " : "", px, py);
    }
    if (drawn)
        fputs("\"/>\n", s->f);
    add_legend(s, label, color, LEG_LINE);
}

void cli_svg_points(cli_svg *s, const double *x, long xs, const double *y, long ys, long n,
                    int color, const char *label)
{
    double px, py;
    for (long i = 0; y && i < n; i++)
        if (map_x(s, xval(x, xs, i), &px) && map_y(s, y[i * ys], &py))
            fprintf(s->f, "<circle class=\"marker\" clip-path=\"url(#clip%d)\" cx=\"%.2f\" "
                          "cy=\"%.2f\" r=\"3\" fill=\"%s\"/>\n", s->panel, px, py, col(color));
    add_legend(s, label, color, LEG_POINT);
}

void cli_svg_errbars(cli_svg *s, const double *x, const double *lo, const double *hi, long n,
                     int color)
{
    double px, a, b;
    for (long i = 0; lo && hi && i < n; i++)
        if (map_x(s, xval(x, 1, i), &px) && map_y(s, lo[i], &a) && map_y(s, hi[i], &b))
            fprintf(s->f, "<path class=\"errbar\" clip-path=\"url(#clip%d)\" stroke=\"%s\" "
                          "fill=\"none\" d=\"M%.2f %.2fV%.2fM%.2f %.2fH%.2fM%.2f %.2fH%.2f\"/>\n",
                    s->panel, col(color), px, a, b, px - 3, a, px + 3, px - 3, b, px + 3);
}

/* One polygon over the valid points i0 .. i1 - 1 of a band. */
static void band_run(cli_svg *s, const double *x, long xs, const double *lo, const double *hi,
                     long bs, long i0, long i1, int color)
{
    double px, py;
    fprintf(s->f, "<polygon class=\"band\" clip-path=\"url(#clip%d)\" fill=\"%s\" "
                  "fill-opacity=\"0.25\" stroke=\"none\" points=\"", s->panel, col(color));
    for (long i = i0; i < i1; i++)
        if (map_x(s, xval(x, xs, i), &px) && map_y(s, hi[i * bs], &py))
            fprintf(s->f, "%s%.2f,%.2f", i > i0 ? " " : "", px, py);
    for (long i = i1 - 1; i >= i0; i--)
        if (map_x(s, xval(x, xs, i), &px) && map_y(s, lo[i * bs], &py))
            fprintf(s->f, " %.2f,%.2f", px, py);
    fputs("\"/>\n", s->f);
}

void cli_svg_band(cli_svg *s, const double *x, long xs, const double *lo, const double *hi,
                  long bs, long n, int color, const char *label)
{
    double p;
    long start = -1;
    for (long i = 0; lo && hi && i <= n; i++) {
        int ok = i < n && map_x(s, xval(x, xs, i), &p) && map_y(s, lo[i * bs], &p) &&
                 map_y(s, hi[i * bs], &p);
        if (ok && start < 0)
            start = i;
        else if (!ok && start >= 0) {
            band_run(s, x, xs, lo, hi, bs, start, i, color);
            start = -1;
        }
    }
    add_legend(s, label, color, LEG_BAND);
}

void cli_svg_hline(cli_svg *s, double y, int color, const char *label)
{
    double py;
    if (map_y(s, y, &py) && py >= s->py && py <= s->py + s->ph)
        fprintf(s->f, "<line class=\"hline\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
                      "stroke=\"%s\" stroke-dasharray=\"5,3\"/>\n",
                s->px, py, s->px + s->pw, py, col(color));
    add_legend(s, label, color, LEG_DASH);
}

void cli_svg_vline(cli_svg *s, double x, int color, const char *label)
{
    double px;
    if (map_x(s, x, &px) && px >= s->px && px <= s->px + s->pw)
        fprintf(s->f, "<line class=\"vline\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
                      "stroke=\"%s\" stroke-dasharray=\"5,3\"/>\n",
                px, s->py, px, s->py + s->ph, col(color));
    add_legend(s, label, color, LEG_DASH);
}

/* ---- the commands' pictures ---------------------------------------------- */

/* The model's term k (or for k < 0 the sum of the supported ones) at tau. */
static double fit_dev(int k, double t, const double *fit, const int *sup)
{
    double f[IGEA_STABILITY_FIT_LEN] = {3 / (t * t), 1 / t,
                                        2 * log(2.0) / 3.14159265358979323846, t / 3, t * t / 2};
    double v = 0;
    for (int i = 0; i < IGEA_STABILITY_FIT_LEN; i++)
        if (k < 0 ? !sup || sup[i] : i == k)
            v += fit[i] * fit[i] * f[i];
    return sqrt(v);
}

/* Widen the deviation axis to the fitted terms where they come within a
 * factor 10 of the data (a term far below the data stays clipped). */
static void fit_range(cli_svg_axis *y, int ntau, const double *tau, const double *fit,
                      const int *sup)
{
    double lo = y->lo, hi = y->hi;
    for (int k = 0; fit && lo <= hi && k < IGEA_STABILITY_FIT_LEN; k++)
        for (int j = 0; (!sup || sup[k]) && j < ntau; j++) {
            double v = fit_dev(k, tau[j], fit, sup);
            if (v >= lo / 10 && v <= hi * 10)
                cli_svg_range(y, &v, 1, 1);
        }
}

/* The IEEE 952 model's terms (3Q^2/tau^2, N^2/tau, (2 ln2/pi) B^2, K^2
 * tau/3, R^2 tau^2/2: igea/stability.h) as deviations at the taus, dashed,
 * and their sum; the terms without support are not drawn. */
static void fit_lines(cli_svg *s, int ntau, const double *tau, const double *fit,
                      const int *sup)
{
    static const char *const label[IGEA_STABILITY_FIT_LEN] = {
        "fit: Q, slope -1", "fit: N, slope -1/2", "fit: B, flat", "fit: K, slope +1/2",
        "fit: R, slope +1"};
    for (int k = -1; k < IGEA_STABILITY_FIT_LEN; k++) { /* -1: the sum */
        if (k >= 0 && sup && !sup[k])
            continue;
        long drawn = 0;
        double px, py;
        for (int j = 0; j < ntau; j++) {
            if (!map_x(s, tau[j], &px) || !map_y(s, fit_dev(k, tau[j], fit, sup), &py))
                continue;
            if (!drawn++)
                fprintf(s->f, "<polyline class=\"fit\" clip-path=\"url(#clip%d)\" fill=\"none\" "
                              "stroke=\"%s\" stroke-width=\"1.2\"%s points=\"", s->panel,
                        col(k + 2), k < 0 ? "" : " stroke-dasharray=\"5,3\"");
            fprintf(s->f, "%s%.2f,%.2f", drawn > 1 ? " " : "", px, py);
        }
        if (drawn)
            fputs("\"/>\n", s->f);
        add_legend(s, k < 0 ? "fit: the sum of the terms" : label[k], k + 2,
                   k < 0 ? LEG_LINE : LEG_DASH);
    }
}

int cli_svg_stability(const char *path, const char *file, const char *kind, int ntau, const double *tau,
                      const double *dev, const double *lo, const double *hi,
                      const double *fit, const int *fit_sup)
{
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec)
        return ec;
    cli_svg s;
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(1, "averaging time tau (s)");
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(1, "deviation (units of the data)");
    cli_svg_range(&x, tau, ntau, 1);
    cli_svg_range(&y, dev, ntau, 1);
    cli_svg_range(&y, lo, lo ? ntau : 0, 1);
    cli_svg_range(&y, hi, hi ? ntau : 0, 1);
    fit_range(&y, ntau, tau, fit, fit_sup);
    size_t tn = strlen(file) + strlen(kind) + 16;
    char *title = malloc(tn);
    if (!title) {
        cli_out_abort(&o);
        return cli_oom("the picture's title");
    }
    snprintf(title, tn, "%s: %s deviation", file, kind);
    cli_svg_begin(&s, o.f, 720, 480, title);
    cli_svg_panel(&s, 0, 0, 720, 480, &x, &y, title);
    free(title);
    if (lo && hi)
        cli_svg_errbars(&s, tau, lo, hi, ntau, 0);
    cli_svg_line(&s, tau, 1, dev, 1, ntau, 0, lo && hi ? "deviation, with its interval" : "deviation");
    cli_svg_points(&s, tau, 1, dev, 1, ntau, 0, NULL);
    if (fit)
        fit_lines(&s, ntau, tau, fit, fit_sup);
    if (fit) {
        static const char *const name[IGEA_STABILITY_FIT_LEN] = {"Q", "N", "B", "K", "R"};
        char line[IGEA_STABILITY_FIT_LEN][48];
        int row = 0;
        for (int k = 0; k < IGEA_STABILITY_FIT_LEN; k++) {
            if (fit_sup && !fit_sup[k])
                snprintf(line[k], sizeof line[k], "IEEE 952 %s: -", name[k]);
            else
                snprintf(line[k], sizeof line[k], "IEEE 952 %s = %.4g", name[k], fit[k]);
            cli_svg_text(&s, s.px + 8, s.py + s.ph - 8 - 14.0 * (IGEA_STABILITY_FIT_LEN - 1 - row++),
                         "start", line[k]);
        }
    }
    cli_svg_end(&s);
    return cli_out_commit(&o);
}

/* The residuals of res (one number a line) from its start, malloc'd. */
static int read_residuals(FILE *res, double **e, long *m)
{
    long cap = 1024, n = 0;
    double v, *buf = malloc(sizeof(double) * (size_t)cap);
    if (!buf)
        return cli_oom("the residuals to plot");
    if (fflush(res) != 0 || fseek(res, 0, SEEK_SET) != 0) {
        free(buf);
        cli_error("--plot: cannot read the residuals back");
        return CLI_IOERR;
    }
    char line[256];
    while (fgets(line, sizeof line, res)) { /* "epoch axis residual" rows under '#' */
        if (line[0] == '#' || sscanf(line, "%*f %*f %lf", &v) != 1)
            continue;
        if (n == cap) {
            double *nb = realloc(buf, sizeof(double) * (size_t)(cap *= 2));
            if (!nb) {
                free(buf);
                return cli_oom("the residuals to plot");
            }
            buf = nb;
        }
        buf[n++] = v;
    }
    *e = buf, *m = n;
    return CLI_OK;
}

static void eqerr_spectrum(cli_svg *s, double top, int N, const double *lambda, double lt,
                           double ls)
{
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, "component i (from 0)");
    x.integer = 1;
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(1, "eigenvalue lambda_i");
    x.lo = 0, x.hi = N > 1 ? N - 1 : 1;
    cli_svg_range(&y, lambda, N, 1);
    cli_svg_range(&y, &lt, 1, 1);
    cli_svg_range(&y, &ls, 1, 1);
    cli_svg_panel(s, 0, top, 720, 360, &x, &y, "eigenvalue spectrum");
    cli_svg_points(s, NULL, 1, lambda, 1, N, 0, "lambda_i");
    char a[48], b[48];
    snprintf(a, sizeof a, "lambda_test = %g", lt);
    snprintf(b, sizeof b, "lambda_small = %g", ls);
    cli_svg_hline(s, lt, 1, a);
    cli_svg_hline(s, ls, 2, b);
    int nonpos = 0;
    for (int i = 0; i < N; i++)
        nonpos += !(lambda[i] > 0);
    if (nonpos) {
        char note[64];
        snprintf(note, sizeof note, "%d eigenvalue(s) <= 0 not drawn", nonpos);
        cli_svg_text(s, s->px + 8, s->py + s->ph - 8, "start", note);
    }
}

int cli_svg_eqerr(const char *path, const cli_out *resout, int N, const double *lambda,
                  double lambda_test, double lambda_small)
{
    double *e = NULL;
    long m = 0;
    FILE *res = NULL;
    int ec = CLI_OK;
    if (resout->f && resout->tmp) { /* --residuals FILE: its temporary, read back */
        if (fflush(resout->f) != 0 || !(res = fopen(resout->tmp, "r"))) {
            cli_error("--plot: cannot read the residuals back from %s", resout->tmp);
            return CLI_IOERR;
        }
    } else if (resout->f && resout->f != stdout && !resout->path) {
        res = resout->f; /* a temporary file of the driver's own */
    }
    if (res)
        ec = read_residuals(res, &e, &m);
    if (res && res != resout->f)
        fclose(res);
    cli_out o;
    if (ec || (ec = cli_out_open(&o, path))) {
        free(e);
        return ec;
    }
    cli_svg s;
    cli_svg_begin(&s, o.f, 720, res ? 720 : 380, "igea eqerr");
    double top = 0;
    if (res) {
        static const char *const axis[3] = {"x", "y", "z"};
        long ne = (m + 2) / 3;
        cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, "epoch (from 0)");
        x.integer = 1;
        cli_svg_axis y = CLI_SVG_AXIS_EMPTY(0, "residual (units of dw)");
        x.lo = 0, x.hi = ne > 1 ? ne - 1 : 1;
        cli_svg_range(&y, e, m, 1);
        cli_svg_panel(&s, 0, 0, 720, 360, &x, &y, "residuals per axis");
        for (int k = 0; k < 3; k++)
            cli_svg_line(&s, NULL, 1, e + k, 3, m > k ? (m - k + 2) / 3 : 0, k, axis[k]);
        top = 360;
    }
    eqerr_spectrum(&s, top, N, lambda, lambda_test, lambda_small);
    if (!res)
        cli_svg_text(&s, 360, 374, "middle", "residuals not drawn: --residuals is standard "
                                            "output or a device");
    cli_svg_end(&s);
    free(e);
    return cli_out_commit(&o);
}

int cli_svg_montecarlo(const char *path, int flights, int N, const int *tested,
                       const int *rejected, double alpha)
{
    double *v = malloc(sizeof(double) * 3 * (size_t)(N > 0 ? N : 1));
    if (!v)
        return cli_oom("the rates to plot");
    double *rate = v, *lo = v + N, *hi = lo + N, lohi[2];
    for (int j = 0; j < N; j++) {
        rate[j] = lo[j] = hi[j] = NAN; /* not tested: not drawn */
        if (tested[j] > 0 && !igea_sim_interval(rejected[j], tested[j], lohi))
            rate[j] = (double)rejected[j] / tested[j], lo[j] = lohi[0], hi[j] = lohi[1];
    }
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec) {
        free(v);
        return ec;
    }
    cli_svg s;
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, "component i (from 0)");
    x.integer = 1;
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(0, "rejection rate (fraction of the flights testing it)");
    x.lo = 0, x.hi = N > 1 ? N - 1 : 1;
    y.lo = 0, y.hi = alpha;
    cli_svg_range(&y, hi, N, 1);
    char title[96], a[48];
    snprintf(title, sizeof title, "per-component rejection rates, %d flights", flights);
    snprintf(a, sizeof a, "alpha = %g", alpha);
    cli_svg_begin(&s, o.f, 720, 480, title);
    cli_svg_panel(&s, 0, 0, 720, 480, &x, &y, title);
    cli_svg_errbars(&s, NULL, lo, hi, N, 0);
    cli_svg_points(&s, NULL, 1, rate, 1, N, 0, "rate, 99 % Wilson interval");
    cli_svg_hline(&s, alpha, 1, a);
    cli_svg_end(&s);
    free(v);
    return cli_out_commit(&o);
}

/* The exclusion intervals as bars, one row per sensor. */
static void fuse_timeline(cli_svg *s, int nwin, double step, int nc, int niv, const int *sensor,
                          const double *t0, const double *t1)
{
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, "time (s)");
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(0, "sensor (from 0)");
    x.lo = 0, x.hi = nwin * step;
    /* one row per sensor, its bar inside the panel; ticks at the sensors */
    y.lo = -0.5, y.hi = (nc > 1 ? nc : 1) - 0.5, y.integer = 1;
    cli_svg_panel(s, 0, 300, 720, 300, &x, &y, "sensors excluded from the fusion set");
    double h = s->ph / (s->y1 - s->y0) * 0.6, a, b, c;
    for (int k = 0; k < niv; k++)
        if (map_x(s, t0[k], &a) && map_x(s, t1[k], &b) && map_y(s, sensor[k], &c))
            fprintf(s->f, "<rect class=\"interval\" clip-path=\"url(#clip%d)\" x=\"%.2f\" "
                          "y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"%s\"/>\n",
                    s->panel, a, c - h / 2, b - a, h, col(1));
    add_legend(s, "excluded", 1, LEG_BAR);
    if (!niv)
        cli_svg_text(s, s->px + s->pw / 2, s->py + s->ph / 2, "middle", "no sensor excluded");
}

int cli_svg_fuse(const char *path, int nwin, double step, const double *fused,
                 const double *fsig, int nc, int niv, const int *sensor, const double *t0,
                 const double *t1)
{
    double *v = malloc(sizeof(double) * 3 * (size_t)(nwin > 0 ? nwin : 1));
    if (!v)
        return cli_oom("the fused output to plot");
    double *t = v, *lo = v + nwin, *hi = lo + nwin;
    for (int w = 0; w < nwin; w++) /* the window's start, as in the report */
        t[w] = w * step, lo[w] = fused[w] - fsig[w], hi[w] = fused[w] + fsig[w];
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec) {
        free(v);
        return ec;
    }
    cli_svg s;
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, "time (s)");
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(0, "fused output (units of the data)");
    x.lo = 0, x.hi = nwin * step;
    cli_svg_range(&y, lo, nwin, 1);
    cli_svg_range(&y, hi, nwin, 1);
    cli_svg_begin(&s, o.f, 720, 600, "igea redund fuse");
    cli_svg_panel(&s, 0, 0, 720, 300, &x, &y, "fused output per window");
    cli_svg_band(&s, t, 1, lo, hi, 1, nwin, 0, "fused +- sigma");
    cli_svg_line(&s, t, 1, fused, 1, nwin, 0, "fused");
    fuse_timeline(&s, nwin, step, nc, niv, sensor, t0, t1);
    cli_svg_end(&s);
    free(v);
    return cli_out_commit(&o);
}

int cli_svg_rls_add(cli_svg_rows *r, const igea_rls *h, int m)
{
    if (r->n == r->cap) {
        long cap = r->cap ? 2 * r->cap : 256;
        double *v = realloc(r->v, sizeof(double) * 2 * (size_t)m * (size_t)cap);
        if (!v)
            return cli_oom("the estimates to plot");
        r->v = v, r->cap = cap;
    }
    double *x = r->v + 2 * (size_t)m * (size_t)r->n, *sd = x + m;
    int st = igea_rls_get_x(h, x);
    if (st)
        return cli_status(st, "rls --plot");
    if (igea_rls_get_sd(h, sd)) /* P no longer tracked: no band at this epoch */
        for (int i = 0; i < m; i++)
            sd[i] = NAN;
    r->n++;
    return CLI_OK;
}

/* Panel i of the estimates: x_i and its 3 sigma band against the epoch. */
static void rls_panel(cli_svg *s, const cli_svg_rows *r, int m, int i, double top, double *band)
{
    long n = r->n, w = 2 * (long)m;
    double *lo = band, *hi = band + n;
    for (long e = 0; e < n; e++) {
        double x = r->v[e * w + i], sd = r->v[e * w + m + i];
        lo[e] = x - 3 * sd, hi[e] = x + 3 * sd;
    }
    char title[48];
    snprintf(title, sizeof title, "coefficient x%d", i);
    cli_svg_axis xa = CLI_SVG_AXIS_EMPTY(0, "epoch (from 0)");
    xa.integer = 1;
    cli_svg_axis ya = CLI_SVG_AXIS_EMPTY(0, "estimate (units of X)");
    xa.lo = 0, xa.hi = n > 1 ? n - 1 : 1;
    cli_svg_range(&ya, r->v + i, n, w);
    cli_svg_range(&ya, lo, n, 1);
    cli_svg_range(&ya, hi, n, 1);
    cli_svg_panel(s, 0, top, 720, 260, &xa, &ya, title);
    cli_svg_band(s, NULL, 1, lo, hi, 1, n, i, "3 sigma (honest)");
    cli_svg_line(s, NULL, 1, r->v + i, w, n, i, "estimate");
}

int cli_svg_rls(const char *path, const cli_svg_rows *r, int m)
{
    int np = m < CLI_SVG_RLS_PANELS ? m : CLI_SVG_RLS_PANELS;
    double *band = malloc(sizeof(double) * 2 * (size_t)(r->n > 0 ? r->n : 1));
    if (!band)
        return cli_oom("the bands to plot");
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec) {
        free(band);
        return ec;
    }
    cli_svg s;
    cli_svg_begin(&s, o.f, 720, 260.0 * np + (m > np ? 24 : 0), "igea rls");
    for (int i = 0; i < np; i++)
        rls_panel(&s, r, m, i, 260.0 * i, band);
    if (m > np) {
        char note[80];
        snprintf(note, sizeof note, "coefficients x0 .. x%d drawn of %d", np - 1, m);
        cli_svg_text(&s, 360, 260.0 * np + 16, "middle", note);
    }
    cli_svg_end(&s);
    free(band);
    return cli_out_commit(&o);
}

/* ---- nav: the navigation errors against time ------------------------------ */

#define NAV_PANEL_H 270.0
#define ARCSEC_PER_RAD 206264.80624709636

/* Widen a linear axis so that its data keep clear of gap pixels at the top
 * (top 1) or the bottom of a plot area len pixels long: the legend's place
 * (plot_range pads 4 % on each side: the old end lands gap / len from the
 * edge). An empty or one-value range is left to plot_range. */
static void make_room(cli_svg_axis *ax, double gap, double len, int top)
{
    if (!(ax->lo < ax->hi) || !(len > 0))
        return;
    double f = gap / len > 0.6 ? 0.6 : gap / len, d = (ax->hi - ax->lo) / (1.04 - 1.08 * f);
    if (top)
        ax->hi = ax->lo + d;
    else
        ax->lo = ax->hi - d;
}

/* The unit of time for a run ending at tend (s): its factor and label. */
static double time_unit(double tend, const char **label)
{
    if (tend >= 3 * 3600.0)
        return *label = "time (h)", 1 / 3600.0;
    if (tend >= 600)
        return *label = "time (min)", 1 / 60.0;
    return *label = "time (s)", 1.0;
}

/* The unit of panel q (0 position, 1 velocity, 2 attitude) for errors up
 * to big (SI): its factor from SI and the axis label, so that the tick
 * labels stay below 1e4 and above 1e-2 where a smaller unit exists. */
static double nav_unit(int q, double big, const char **label)
{
    if (q == 0)
        return big < 1e4 ? (*label = "position error (m)", 1.0)
                         : (*label = "position error (km)", 1e-3);
    if (q == 1)
        return big < 1e-2 ? (*label = "velocity error (mm/s)", 1e3)
                          : (*label = "velocity error (m/s)", 1.0);
    return big * ARCSEC_PER_RAD < 1e4 ? (*label = "attitude error phi (arcsec)", ARCSEC_PER_RAD)
                                      : (*label = "attitude error phi (deg)",
                                         180 / 3.14159265358979323846);
}

/* The epochs drawn: every k-th of n and the last, at most
 * CLI_SVG_NAV_POINTS; returns how many, idx[] their indices. */
static long nav_epochs(long n, long *idx)
{
    long k = (n + CLI_SVG_NAV_POINTS - 2) / (CLI_SVG_NAV_POINTS - 1), m = 0;
    for (long i = 0; i < n; i += k)
        idx[m++] = i;
    if (n > 0 && idx[m - 1] != n - 1)
        idx[m++] = n - 1;
    return m;
}

/* Panel q of the nav picture: its three errors (and bands) from v, m
 * epochs, rows of 9 (the response scaled) then 9 (sd scaled, or none). */
static void nav_panel(cli_svg *s, double top, long m, const double *tt, double *v,
                      int bands, int li, const char *unit_label, const char *title,
                      const char *tlabel)
{
    static const char *const ned[3] = {"north", "east", "down"};
    static const char *const xyz[3] = {"x", "y", "z"};
    static const char *const band = "shaded: \xc2\xb1" "1\xcf\x83 of the sensor noise";
    const char *const *axis = li ? xyz : ned;
    double *y = v, *lo = v + 3 * m, *hi = v + 6 * m; /* y[a m + i] */
    cli_svg_axis xa = CLI_SVG_AXIS_EMPTY(0, tlabel), ya = CLI_SVG_AXIS_EMPTY(0, unit_label);
    cli_svg_range(&xa, tt, m, 1);
    cli_svg_range(&ya, y, 3 * m, 1);
    if (bands) {
        cli_svg_range(&ya, lo, 3 * m, 1);
        cli_svg_range(&ya, hi, 3 * m, 1);
    }
    const char *labels[4] = {axis[0], axis[1], axis[2], band};
    make_room(&ya, row_legend_height(labels, bands ? 4 : 3, 720 - 90) + 12, NAV_PANEL_H - 72, 1);
    cli_svg_panel(s, 0, top, 720, NAV_PANEL_H, &xa, &ya, title);
    s->legrow = 1;
    for (int a = 0; bands && a < 3; a++)
        cli_svg_band(s, tt, 1, lo + a * m, hi + a * m, 1, m, a, NULL);
    for (int a = 0; a < 3; a++)
        cli_svg_line(s, tt, 1, y + a * m, 1, m, a, axis[a]);
    if (bands)
        add_legend(s, band, 7, LEG_BAND);
}

int cli_svg_nav(const char *path, const char *what, int li, int n, const double *t, double dt,
                const double *x, const double *P)
{
    long *idx = malloc(sizeof(long) * (size_t)(n > 0 ? n : 1));
    long m = idx ? nav_epochs(n, idx) : 0;
    /* the epochs drawn (scaled), then per panel 9 m values: y, lo, hi */
    double *v = idx ? malloc(sizeof(double) * 10 * (size_t)(m > 0 ? m : 1)) : NULL;
    if (!v) {
        free(idx);
        return cli_oom("the errors to plot");
    }
    const char *tlabel;
    double tend = n > 0 ? (t ? t[n - 1] : (n - 1) * dt) : 0, tf = time_unit(tend, &tlabel);
    double *tt = v, *w = v + m;
    for (long i = 0; i < m; i++)
        tt[i] = (t ? t[idx[i]] : idx[i] * dt) * tf;
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec) {
        free(v);
        free(idx);
        return ec;
    }
    static const char *const quantity[3] = {"position error", "velocity error",
                                            "attitude error"};
    char title[3][256];
    for (int q = 0; q < 3; q++) { /* the frame in every title along a trajectory */
        const char *tail = q == 0 && what ? what : li ? "launch-inertial axes" : NULL;
        snprintf(title[q], sizeof title[q], "%s%s%s", quantity[q], tail ? ", " : "",
                 tail ? tail : "");
    }
    cli_svg s;
    cli_svg_begin(&s, o.f, 720, 3 * NAV_PANEL_H, "igea nav");
    for (int q = 0; q < 3; q++) {
        double big = 0;
        for (long i = 0; i < m; i++)
            for (int a = 0; a < 3; a++) {
                size_t k = (size_t)idx[i], j = (size_t)(3 * q + a);
                double e = x[k * IGEA_INSERR_N + j];
                double sd = P ? sqrt(fmax(P[(k * IGEA_INSERR_N + j) * IGEA_INSERR_N + j], 0))
                              : 0;
                w[a * m + i] = e, w[(3 + a) * m + i] = e - sd, w[(6 + a) * m + i] = e + sd;
                big = fmax(big, fabs(e) + sd);
            }
        const char *label;
        double f = nav_unit(q, big, &label);
        for (long i = 0; i < 9 * m; i++)
            w[i] *= f;
        nav_panel(&s, q * NAV_PANEL_H, m, tt, w, P != NULL, li, label,
                  title[q], tlabel);
    }
    cli_svg_end(&s);
    free(v);
    free(idx);
    return cli_out_commit(&o);
}

/* ---- impact: the impact plane and the budget's shares --------------------- */

#define IMPACT_W 1080.0
#define IMPACT_H 500.0
#define PLANE_W 480.0
#define ELLIPSE_POINTS 360

/* The k-sigma ellipse of the covariance of eigenvalues l1 >= l2 >= 0, the
 * first axis at angle a from x (radians), about the origin, f the unit's
 * factor: a closed polygon through ELLIPSE_POINTS points from the end of
 * the major axis. */
static void impact_ellipse(cli_svg *s, double l1, double l2, double a, double k, double f,
                           int color, const char *label)
{
    fprintf(s->f, "<polygon class=\"ellipse\" data-k=\"%g\" clip-path=\"url(#clip%d)\" "
                  "fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", k, s->panel,
            col(color));
    int first = 1;
    for (int i = 0; i < ELLIPSE_POINTS; i++) {
        double t = 2 * 3.14159265358979323846 * i / ELLIPSE_POINTS;
        double u = k * sqrt(l1) * cos(t), w = k * sqrt(l2) * sin(t), px, py;
        if (map_x(s, f * (u * cos(a) - w * sin(a)), &px) &&
            map_y(s, f * (u * sin(a) + w * cos(a)), &py))
            fprintf(s->f, "%s%.2f,%.2f", first ? "" : " ", px, py), first = 0;
    }
    fputs("\"/>\n", s->f);
    add_legend(s, label, color, LEG_LINE);
}

/* The impact plane: x crossrange, y downrange (a map seen from above with
 * the flight going up), equal scales, the ellipses and the circle. */
static void impact_plane(cli_svg *s, const double *cov, double prob, double radius,
                         const char *circle_label)
{
    /* k sigma holds 1 - exp(-k^2/2): 39.3 % and 98.9 % */
    static const char *const e1 = "1\xcf\x83 ellipse (39.3 %)";
    static const char *const e3 = "3\xcf\x83 ellipse (98.9 %)";
    /* (x, y) = (crossrange, downrange): cov is downrange first */
    double a = cov[3], c = cov[0], b = 0.5 * (cov[1] + cov[2]);
    double h = hypot(0.5 * (a - c), b), l1 = 0.5 * (a + c) + h, l2 = fmax(0.5 * (a + c) - h, 0);
    double ang = 0.5 * atan2(2 * b, a - c);
    double hx = fmax(3 * sqrt(fmax(a, 0)), radius), hy = fmax(3 * sqrt(fmax(c, 0)), radius);
    if (!(hx > 0 && hy > 0))
        hx = hy = fmax(fmax(hx, hy), 1);
    double f = fmax(hx, hy) >= 1e4 ? 1e-3 : 1; /* km beyond 10 km */
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, f < 1 ? "crossrange (km, right of the flight)"
                                                 : "crossrange (m, right of the flight)");
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(0, f < 1 ? "downrange (km)" : "downrange (m)");
    x.lo = -f * hx, x.hi = f * hx, y.lo = -f * hy, y.hi = f * hy;
    double pw = PLANE_W - 90, ph = IMPACT_H - 72;
    const char *labels[3] = {e1, e3, circle_label};
    make_room(&y, row_legend_height(labels, 3, pw) + 12, ph, 1);
    /* equal scales: widen the axis with fewer units a pixel (both get the
     * same 4 % pad in plot_range) */
    double ux = (x.hi - x.lo) / pw, uy = (y.hi - y.lo) / ph;
    if (ux < uy)
        x.lo = -0.5 * uy * pw, x.hi = 0.5 * uy * pw;
    else {
        double grow = 0.5 * (ux * ph - (y.hi - y.lo));
        y.lo -= grow, y.hi += grow;
    }
    cli_svg_panel(s, 0, 0, PLANE_W, IMPACT_H, &x, &y, "miss about the mean impact point");
    s->legrow = 1;
    impact_ellipse(s, l1, l2, ang, 1, f, 0, e1);
    impact_ellipse(s, l1, l2, ang, 3, f, 2, e3);
    double cx, cy, rx;
    if (map_x(s, 0, &cx) && map_y(s, 0, &cy) && map_x(s, f * radius, &rx))
        fprintf(s->f, "<circle class=\"cep\" clip-path=\"url(#clip%d)\" cx=\"%.2f\" cy=\"%.2f\" "
                      "r=\"%.2f\" fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" "
                      "stroke-dasharray=\"5,3\"/>\n"
                      "<path class=\"mean\" d=\"M%.2f %.2fH%.2fM%.2f %.2fV%.2f\" "
                      "stroke=\"black\"/>\n",
                s->panel, cx, cy, rx - cx, col(1), cx - 5, cy, cx + 5, cx, cy - 5, cy + 5);
    add_legend(s, circle_label, 1, LEG_DASH);
    (void)prob;
}

typedef struct {
    double share;
    int j;
} share_index;

static int by_share_desc(const void *pa, const void *pb)
{
    const share_index *a = pa, *b = pb;
    return a->share > b->share ? -1 : a->share < b->share ? 1 : (a->j > b->j) - (a->j < b->j);
}

/* A bar's label: the term's name (term_j without names), cut to 24
 * characters (21 and "..."). */
static void bar_name(char *buf, size_t size, char *const *names, int j)
{
    if (names)
        snprintf(buf, size, "%s", names[j]);
    else
        snprintf(buf, size, "term_%d", j);
    size_t chars = 0, cut = 0, k = 0;
    for (; buf[k]; k++)
        if ((((unsigned char)buf[k]) & 0xC0) != 0x80) { /* a character starts */
            if (++chars == 22)
                cut = k;
            if (chars > 24)
                break;
        }
    if (buf[k] && cut + 4 <= size)
        memcpy(buf + cut, "...", 4);
}

/* The shares as horizontal bars, largest at the top, each split into its
 * downrange and crossrange parts (share_j m_d^2 / |m_j|^2 and the rest). */
static void impact_bars(cli_svg *s, int n, char *const *names, const double *miss,
                        const double *share, share_index *order, char (*label)[112])
{
    for (int j = 0; j < n; j++)
        order[j].share = share[j], order[j].j = j;
    qsort(order, (size_t)n, sizeof *order, by_share_desc);
    int nb = n <= CLI_SVG_IMPACT_BARS ? n : CLI_SVG_IMPACT_BARS + 1;
    double top = 0, chars = 0;
    for (int i = 0; i < nb; i++) {
        if (i < CLI_SVG_IMPACT_BARS)
            bar_name(label[i], sizeof label[i], names, order[i].j);
        else
            snprintf(label[i], sizeof label[i], "the other %d terms", n - CLI_SVG_IMPACT_BARS);
        chars = fmax(chars, label_chars(label[i]));
    }
    double sh[CLI_SVG_IMPACT_BARS + 1] = {0}, down[CLI_SVG_IMPACT_BARS + 1] = {0};
    for (int k = 0; k < n; k++) {
        int i = k < CLI_SVG_IMPACT_BARS ? k : CLI_SVG_IMPACT_BARS, j = order[k].j;
        double md = miss[2 * j], mc = miss[2 * j + 1], m2 = md * md + mc * mc;
        sh[i] += 100 * share[j];
        down[i] += m2 > 0 ? 100 * share[j] * (md * md / m2) : 0;
    }
    for (int i = 0; i < nb; i++)
        top = fmax(top, sh[i]);
    double px = PLANE_W + 24 + 7 * chars, width = IMPACT_W - 20 - px + 90;
    cli_svg_axis x = CLI_SVG_AXIS_EMPTY(0, "share of the trace of the impact covariance (%)");
    cli_svg_axis y = CLI_SVG_AXIS_EMPTY(0, "");
    x.lo = 0, x.hi = top > 0 ? top : 1;
    /* at least 8 slots: a few bars stay slim, at the top */
    y.lo = nb - 0.5 - (nb > 8 ? nb : 8), y.hi = nb - 0.5, y.noticks = 1;
    make_room(&x, 60, width - 90, 1); /* the value beside the longest bar */
    const char *leg[2] = {"downrange part", "crossrange part"};
    make_room(&y, row_legend_height(leg, 2, width - 90) + 12, IMPACT_H - 72, 0);
    char title[96];
    if (n > CLI_SVG_IMPACT_BARS)
        snprintf(title, sizeof title, "shares, largest first: %d of %d terms and the rest",
                 CLI_SVG_IMPACT_BARS, n);
    else
        snprintf(title, sizeof title, "shares, largest first");
    cli_svg_panel(s, px - 70, 0, width, IMPACT_H, &x, &y, title);
    s->legrow = 1, s->legbottom = 1;
    double bh = 0.7 * s->ph / (s->y1 - s->y0);
    for (int i = 0; i < nb; i++) {
        double c, x0, xd, xs;
        if (!map_y(s, nb - 1 - i, &c) || !map_x(s, 0, &x0) || !map_x(s, down[i], &xd) ||
            !map_x(s, sh[i], &xs))
            continue;
        fprintf(s->f, "<rect class=\"bar\" data-part=\"downrange\" x=\"%.2f\" y=\"%.2f\" "
                      "width=\"%.2f\" height=\"%.2f\" fill=\"%s\"/>\n"
                      "<rect class=\"bar\" data-part=\"crossrange\" x=\"%.2f\" y=\"%.2f\" "
                      "width=\"%.2f\" height=\"%.2f\" fill=\"%s\"/>\n",
                x0, c - bh / 2, xd - x0, bh, col(0), xd, c - bh / 2, xs - xd, bh, col(1));
        char value[32];
        if (sh[i] < 0.01 && sh[i] > 0)
            snprintf(value, sizeof value, "< 0.01 %%");
        else
            snprintf(value, sizeof value, "%.3g %%", sh[i]);
        cli_svg_text(s, s->px - 8, c + 4, "end", label[i]);
        cli_svg_text(s, xs + 4, c + 4, "start", value);
    }
    add_legend(s, leg[0], 0, LEG_BAR);
    add_legend(s, leg[1], 1, LEG_BAR);
}

int cli_svg_impact(const char *path, int n, char *const *names, const double *miss,
                   const double *share, const double *cov, double prob, double radius)
{
    share_index *order = malloc(sizeof(share_index) * (size_t)(n > 0 ? n : 1));
    if (!order)
        return cli_oom("the shares to plot");
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec) {
        free(order);
        return ec;
    }
    char circle[64], label[CLI_SVG_IMPACT_BARS + 1][112];
    if (prob == 0.5)
        snprintf(circle, sizeof circle, "CEP %.4g m (50 %%)", radius);
    else
        snprintf(circle, sizeof circle, "circle of %g %%: %.4g m", 100 * prob, radius);
    cli_svg s;
    cli_svg_begin(&s, o.f, IMPACT_W, IMPACT_H, "igea impact: the miss budget");
    impact_plane(&s, cov, prob, radius, circle);
    impact_bars(&s, n, names, miss, share, order, label);
    cli_svg_end(&s);
    free(order);
    return cli_out_commit(&o);
}
