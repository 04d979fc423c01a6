/* tests/fuzz/fuzz_text.c - libFuzzer target: the text matrix reader, whole
 * against streamed (harness.h, fz_reader). */
#include "harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fz_reader("m.txt", data, size);
}
