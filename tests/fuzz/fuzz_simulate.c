/* tests/fuzz/fuzz_simulate.c - libFuzzer target: 'igea simulate' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {"--duration", "10", "--rate", "10", NULL};

/* A short synthetic flight (at most 2000 samples and 2000 epochs). */
static int guard(const fz_run *r)
{
    double dur = fz_opt_num(r, "--duration", 120.0), rate = fz_opt_num(r, "--rate", 50.0);
    double step = fz_opt_num(r, "--epoch-step", 1.0);
    if (dur * rate > 2000.0)
        return 1;
    if (fz_has(r, "--traj") || fz_has(r, "--epochs"))
        dur = dur > fz_max_abs(r) ? dur : fz_max_abs(r);
    return !(step > 0) || dur / step > 2000.0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("simulate", cmd_simulate, prefix, 0, guard, data, size);
}
