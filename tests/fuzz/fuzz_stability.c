/* tests/fuzz/fuzz_stability.c - libFuzzer target: 'igea stability' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("stability", cmd_stability, prefix, 0, NULL, data, size);
}
