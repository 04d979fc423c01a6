/* tests/fuzz/fuzz_eqerr.c - libFuzzer target: 'igea eqerr' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

/* Iterations of the sigma_w loop are bounded so a run stays short. */
static int guard(const fz_run *r) { return fz_opt_num(r, "--max-iter", 10) > 100; }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("eqerr", cmd_eqerr, prefix, FZ_VERDICT, guard, data, size);
}
