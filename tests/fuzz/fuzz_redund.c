/* tests/fuzz/fuzz_redund.c - libFuzzer target: 'igea redund' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("redund", cmd_redund, prefix, 0, NULL, data, size);
}
