/* tests/fuzz/fuzz_rls.c - libFuzzer target: 'igea rls' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

/* rls prints each epoch as it reads the stream: a bad row after good ones
 * fails after lines were printed (with --out nothing is committed). */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("rls", cmd_rls, prefix, FZ_STREAMS, NULL, data, size);
}
