/* tests/fuzz/fuzz_test.c - libFuzzer target: 'igea test' in process (harness.h). */
#include "harness.h"

#include "cli.h"

static const char *const prefix[] = {NULL};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_command("test", cmd_test, prefix, FZ_VERDICT, NULL, data, size);
}
