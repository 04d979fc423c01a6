/* bench/launch_point.c - the launch-point columns against the raw records,
 * split into the parts of docs/envfun.md ("With the stated launch point"):
 *
 *   cc -O2 -Iinclude bench/launch_point.c -o build/launch_point -Lbuild/lib -ligea \
 *      -lm -Wl,-rpath,$PWD/build/lib
 *   build/launch_point SYSTEM KIND DX DZ [history]
 *
 * SYSTEM 0 strapdown, 1 platform; KIND 0 apparent, 1 navigated (S of the
 * velocity or velocity_g kind); DX, DZ the launch-point error (m). The
 * reference boost of igea_sim_trajectory (120 s, 50 Hz, epochs every
 * second), site 40.96 N 100.29 E 1000 m, azimuth 30 deg, tracking in ECEF.
 * For d = s (DX, DZ), s = 4 .. 1/8, it prints max |S X|, the odd part of
 * dW less S X, (dW(d) - dW(-d))/2 - S(d) d, whose first-order part is what
 * S misses (S is computed at the stated site of +d, so an O(d^2) rest is
 * S's own dependence on the site), and the even part (dW(d) + dW(-d))/2,
 * O(d^2) plus dw's floor dW(0). With a fifth argument it also prints the
 * odd part's rest every 10 s at s = 1 (its time history).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "igea.h"

#define PI 3.14159265358979323846
#define NEP 120

static double *TRAJ, SITE[IGEA_NAV_SITE_LEN], EP[NEP];
static int NS, SYS, KIND;

static void raw_dw(double dx, double dz, double *dw, double *stated)
{
    double *tel = malloc(sizeof(double) * (size_t)NS * 7), trk[NEP * 7], q0[4];
    double err[IGEA_ENVFUN_TERM_END] = {0};
    int bad;
    err[IGEA_ENVFUN_TERM_POS0_X] = dx;
    err[IGEA_ENVFUN_TERM_POS0_Z] = dz;
    if (!tel ||
        igea_sim_raw(SYS, NS, TRAJ, NS, IGEA_ENVFUN_TERM_END, err, NULL, SITE, IGEA_NAV_ECEF,
                     NEP, EP, NULL, tel, NS, trk, NEP, q0, stated) ||
        igea_dw_compute(stated, SYS, KIND, q0, 0.0, NS, tel, NS, SYS ? 4 : 7, IGEA_NAV_ECEF,
                        NEP, trk, NEP, 7, dw, NULL, NULL, &bad)) {
        fprintf(stderr, "launch_point: igea_sim_raw or igea_dw_compute failed\n");
        exit(1);
    }
    free(tel);
}

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: launch_point SYSTEM KIND DX DZ [history]\n");
        return 64;
    }
    SYS = atoi(argv[1]);
    KIND = atoi(argv[2]);
    double dx = atof(argv[3]), dz = atof(argv[4]);
    static const double scale[6] = {4.0, 2.0, 1.0, 0.5, 0.25, 0.125};
    int codes[2] = {IGEA_ENVFUN_TERM_POS0_X, IGEA_ENVFUN_TERM_POS0_Z};
    int out = KIND ? IGEA_ENVFUN_VELOCITY_G : IGEA_ENVFUN_VELOCITY;
    if (igea_sim_trajectory_length(120.0, 50.0, &NS))
        return 1;
    TRAJ = malloc(sizeof(double) * (size_t)NS * IGEA_ENVFUN_TRAJ_COLS);
    if (!TRAJ || igea_sim_trajectory(SYS, 120.0, 50.0, NS, TRAJ, NS) ||
        igea_nav_site(40.96 * PI / 180, 100.29 * PI / 180, 1000.0, 30.0 * PI / 180, SITE))
        return 1;
    for (int e = 0; e < NEP; e++)
        EP[e] = e + 1.0;
    for (int h = 0; h < 6; h++) {
        double s = scale[h], dp[3 * NEP], dm[3 * NEP], S[6 * NEP];
        double sp[IGEA_NAV_SITE_LEN], sm[IGEA_NAV_SITE_LEN], mo = 0.0, me = 0.0, ms = 0.0;
        raw_dw(s * dx, s * dz, dp, sp);
        raw_dw(-s * dx, -s * dz, dm, sm);
        if (igea_envfun_compute_site(SYS, NS, TRAJ, NS, 2, codes, NULL, 0, NULL, NULL, NS, NEP,
                                     EP, NULL, out, sp, S, 3 * NEP))
            return 1;
        for (int i = 0; i < 3 * NEP; i++) {
            double sx = S[i] * s * dx + S[i + 3 * NEP] * s * dz;
            double odd = 0.5 * (dp[i] - dm[i]) - sx, even = 0.5 * (dp[i] + dm[i]);
            mo = fmax(mo, fabs(odd));
            me = fmax(me, fabs(even));
            ms = fmax(ms, fabs(sx));
            if (argc > 5 && s == 1.0 && (i / 3) % 10 == 9)
                printf("  t %3d s axis %d: odd - S X % .4e, even % .4e, S X % .4e\n", i / 3 + 1,
                       i % 3, odd, even, sx);
        }
        printf("scale %5.3f: max |S X| %.4e, odd part - S X %.4e, even part %.4e m/s\n", s, ms,
               mo, me);
    }
    free(TRAJ);
    return 0;
}
