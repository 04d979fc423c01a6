/* tests/fuzz/fuzz_montecarlo.c - libFuzzer target: 'igea montecarlo' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {"--flights", "2", "--threads", "1", "--duration", "10", "--rate", "10", NULL};

/* A few flights of a short synthetic flight. */
static int guard(const fz_run *r)
{
    double dur = fz_opt_num(r, "--duration", 120.0), rate = fz_opt_num(r, "--rate", 50.0);
    double step = fz_opt_num(r, "--epoch-step", 1.0);
    if (fz_opt_num(r, "--flights", 2000) > 4 || fz_opt_num(r, "--threads", 0) > 2 ||
        fz_opt_num(r, "--threads", 0) < 1 || dur * rate > 2000.0)
        return 1;
    if (fz_has(r, "--traj") || fz_has(r, "--epochs"))
        dur = dur > fz_max_abs(r) ? dur : fz_max_abs(r);
    return !(step > 0) || dur / step > 1000.0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("montecarlo", cmd_montecarlo, prefix, 0, guard, data, size);
}
