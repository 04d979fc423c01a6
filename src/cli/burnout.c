/* The burnout state and the burnout errors of error terms from a
 * trajectory, its launch point and a burnout time (igea_impact_burnout):
 * the options shared by igea eqerr and igea impact. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define DEG (3.14159265358979323846 / 180.0)

int cli_burnout_check(const char *cmd, const cli_burnout_args *b)
{
    int any = b->given_time || b->traj || b->given_lat || b->given_lon || b->given_az ||
              b->given_height || b->given_system || b->axes;
    if (!any)
        return CLI_OK;
    const char *miss = !b->given_time ? "--burnout-time" : !b->traj ? "--traj"
                       : !b->given_lat ? "--lat" : !b->given_lon ? "--lon"
                       : !b->given_az ? "--azimuth" : NULL;
    if (miss) {
        cli_error("%s: the burnout from a trajectory needs --burnout-time, --traj, --lat, --lon "
                  "and --azimuth; %s is missing", cmd, miss);
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* The gyro axes of --axes (platform), or NULL. */
static int read_axes(const cli_burnout_args *b, int *ax, const int **out)
{
    *out = NULL;
    if (!b->axes)
        return CLI_OK;
    char **items;
    int n, ec = cli_split_list(b->axes, &items, &n);
    if (ec)
        return ec;
    if (n != 6)
        ec = cli_usage("--axes: six comma-separated axis numbers 0..2");
    for (int i = 0; i < n && !ec; i++)
        ec = cli_parse_int("--axes", items[i], &ax[i]);
    free(items);
    *out = ec ? NULL : ax;
    return ec;
}

int cli_burnout_compute(const cli_burnout_args *b, int n, const int *codes, const double *spec,
                        double *state, double *E)
{
    double site[IGEA_NAV_SITE_LEN], *traj = NULL;
    int ax[6], nsamp, ec;
    const int *axes;
    if (igea_nav_site(b->lat * DEG, b->lon * DEG, b->height, b->azimuth * DEG, site))
        return cli_usage("--lat, --lon, --height, --azimuth: |lat| < 90, height > -6e6 m");
    if ((ec = read_axes(b, ax, &axes)) || (ec = cli_read_traj(b->traj, &traj, &nsamp)))
        return ec;
    int st = igea_impact_burnout(b->system, nsamp, traj, nsamp, n, codes, axes, spec, site,
                                 b->time, state, E, 6);
    if (st == -10) {
        cli_error("--burnout-time %g: outside the trajectory %s (%g .. %g s)", b->time, b->traj,
                  traj[0], traj[nsamp - 1]);
        ec = CLI_USAGE;
    } else if (st == -3) {
        cli_error("%s: the times must increase strictly", b->traj);
        ec = CLI_DATAERR;
    } else if (st == -7) {
        ec = cli_usage("--axes: platform gyro axes 0..2 (and a term that reads a gyro's output "
                       "axis needs its input and spin axes apart)");
    } else if (st == IGEA_EDOMAIN) {
        cli_error("%s: a quaternion of zero norm", b->traj);
        ec = CLI_DATAERR;
    } else if (st == IGEA_ENONFINITE) {
        cli_error("%s: a value that is not finite (or the burnout state overflows)", b->traj);
        ec = CLI_DATAERR;
    } else {
        ec = cli_status(st, "the burnout from --burnout-time");
    }
    free(traj);
    return ec;
}
