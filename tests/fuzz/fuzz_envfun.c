/* tests/fuzz/fuzz_envfun.c - libFuzzer target: 'igea envfun' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

/* The epoch count follows the time span of the trajectory. */
static int guard(const fz_run *r)
{
    double step = fz_opt_num(r, "--epoch-step", 1.0);
    return !(step > 0) || fz_max_abs(r) / step > 20000.0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("envfun", cmd_envfun, prefix, 0, guard, data, size);
}
