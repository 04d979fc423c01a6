/* tests/fuzz/fuzz_accel.c - libFuzzer target: 'igea accel' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("accel", cmd_accel, prefix, 0, NULL, data, size);
}
