/* failmalloc.c - LD_PRELOAD shim for out-of-memory tests of the driver.
 *
 * With IGEA_FAILMALLOC=n in the environment, the n-th call of malloc, calloc
 * or realloc counted from the start of main() returns NULL with errno =
 * ENOMEM (allocations of the dynamic loader and of library constructors
 * before main are not counted). When the failure fires and
 * IGEA_FAILMALLOC_LOG names a file, "fired" is written there, so that a test
 * can tell a run that recovered from one that never reached the n-th call.
 *
 * Allocations made directly by OpenBLAS are neither counted nor failed:
 * its small-matrix GEMM kernels for AVX-512 processors (SkylakeX,
 * Cooperlake, Sapphire Rapids: dgemm_small_kernel_b0_nn_*) call malloc for
 * a packing buffer of a few hundred bytes and use the result unchecked, so
 * a failure there is a segfault inside OpenBLAS whatever igea does; on other
 * processors those kernels are not taken and the count is the same.
 *
 * Build: cc -shared -fPIC -o failmalloc.so failmalloc.c -ldl */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);

static long fail_at = -1;
static long calls;
static int armed;
static char log_path[4096];

/* The caller of malloc is OpenBLAS (see above). */
static int from_openblas(const void *ra)
{
    Dl_info di;
    return dladdr(ra, &di) && di.dli_fname && strstr(di.dli_fname, "libopenblas");
}

static int should_fail(const void *ra)
{
    if (!armed || from_openblas(ra))
        return 0;
    if (++calls != fail_at)
        return 0;
    if (log_path[0]) {
        int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            if (write(fd, "fired\n", 6) < 0) {
                /* nothing to do */
            }
            close(fd);
        }
    }
    errno = ENOMEM;
    return 1;
}

void *malloc(size_t n)
{
    return should_fail(__builtin_return_address(0)) ? NULL : __libc_malloc(n);
}

void *calloc(size_t n, size_t k)
{
    return should_fail(__builtin_return_address(0)) ? NULL : __libc_calloc(n, k);
}

void *realloc(void *p, size_t n)
{
    return should_fail(__builtin_return_address(0)) ? NULL : __libc_realloc(p, n);
}

typedef int (*main_fn)(int, char **, char **);
static main_fn real_main;

static int counted_main(int argc, char **argv, char **envp)
{
    const char *s = getenv("IGEA_FAILMALLOC"), *lg = getenv("IGEA_FAILMALLOC_LOG");
    if (lg && strlen(lg) < sizeof log_path)
        strcpy(log_path, lg);
    if (s) {
        fail_at = atol(s);
        armed = 1;
    }
    return real_main(argc, argv, envp);
}

int __libc_start_main(main_fn main, int argc, char **argv, void (*init)(void),
                      void (*fini)(void), void (*rtld_fini)(void), void *stack_end)
{
    int (*next)(main_fn, int, char **, void (*)(void), void (*)(void), void (*)(void),
                void *) = (int (*)(main_fn, int, char **, void (*)(void), void (*)(void),
                                   void (*)(void), void *))dlsym(RTLD_NEXT, "__libc_start_main");
    real_main = main;
    return next(counted_main, argc, argv, init, fini, rtld_fini, stack_end);
}
