/* tests/fuzz/fuzz_npy.c - libFuzzer target: the .npy reader, whole against
 * streamed (harness.h, fz_reader). */
#include "harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_reader("m.npy", data, size);
}
