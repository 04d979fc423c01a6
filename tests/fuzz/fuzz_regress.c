/* tests/fuzz/fuzz_regress.c - libFuzzer target: 'igea regress' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("regress", cmd_regress, prefix, 0, NULL, data, size);
}
