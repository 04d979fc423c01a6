/* tests/oom.h - the program's own malloc, which can fail the n-th
 * allocation made inside a call (SQLite's out-of-memory loop):
 *     oom_calls = 0; oom_fail_at = k;  call();  oom_fail_at = -1;
 * glibc's __libc_malloc does the real work, so free and realloc stay the C
 * library's. Not under AddressSanitizer, which owns malloc itself: there
 * OOM_DISABLED is defined and the tests that need the hook skip. Include
 * it in one translation unit per test program. */
#ifndef IGEA_TEST_OOM_H
#define IGEA_TEST_OOM_H

#include <stddef.h>

#if defined(__SANITIZE_ADDRESS__)
#define OOM_DISABLED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OOM_DISABLED 1
#endif
#endif

#ifndef OOM_DISABLED
extern void *__libc_malloc(size_t);
static long oom_fail_at = -1, oom_calls = 0;
void *malloc(size_t n)
{
    if (oom_fail_at >= 0 && oom_calls++ == oom_fail_at)
        return NULL;
    return __libc_malloc(n);
}
#define OOM_ARM(k) (oom_calls = 0, oom_fail_at = (k))
#define OOM_DISARM() (oom_fail_at = -1)
#endif

#endif
