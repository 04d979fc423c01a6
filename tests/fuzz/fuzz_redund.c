/* tests/fuzz/fuzz_redund.c - libFuzzer target: 'igea redund' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

/* The detection / isolation reliability enumerates the 2^n subsets of the
 * n axes (n <= 20 by design): a few axes keep a run short. */
static int guard(const fz_run *r) { return fz_values(r, fz_opt_str(r, "--axes")) > 30; }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("redund", cmd_redund, prefix, 0, guard, data, size);
}
