#!/bin/sh
# tests/fuzz/run.sh - set-up and runs of the libFuzzer targets (fuzz.mk).
#   run.sh deps            clang with libFuzzer usable (installed as root on
#                          Debian when missing); exit 1 if not
#   run.sh quick SECONDS   replay the seed corpus, then fuzz each target
#   run.sh long SECONDS    fuzz each target on the build's growing corpus
# Environment: FUZZ_BUILD (output directory), FUZZ_CC, FUZZ_TARGETS.
set -u
B=${FUZZ_BUILD:-build/fuzz}
CC=${FUZZ_CC:-clang}
SEEDS=tests/fuzz/corpus

probe() {
    mkdir -p "$B" || return 1
    printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n)\n{ (void)d; (void)n; return 0; }\n' \
        > "$B/probe.c" &&
    "$CC" -fsanitize=fuzzer,address,undefined "$B/probe.c" -o "$B/probe" >/dev/null 2>&1 &&
    "$B/probe" -runs=1 >/dev/null 2>&1
}

deps() {
    probe && return 0
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "installing: clang (libFuzzer)"
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq clang >/dev/null ||
            return 1
        probe && return 0
        # the sanitizer and libFuzzer runtimes are a separate package on some releases
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libclang-rt-dev >/dev/null 2>&1
        probe && return 0
    fi
    echo "the fuzz targets need clang with libFuzzer (-fsanitize=fuzzer); install it with:"
    echo "  sudo apt-get install clang"
    return 1
}

# The dictionary of a command target: its options and keywords, taken from
# the command's source so that a new option is fuzzed without editing this.
dict() {
    t=$1
    case $t in
    text) printf '"#"\n","\n"nan"\n"inf"\n"1e308"\n"-0"\n"0x1p-1074"\n"\\x00"\n"\\x0d\\x0a"\n'; return ;;
    npy) printf '"\\x93NUMPY\\x01\\x00"\n"\\x93NUMPY\\x02\\x00"\n"'"'"'descr'"'"'"\n"'"'"'<f8'"'"'"\n"'"'"'fortran_order'"'"'"\n"True"\n"False"\n"'"'"'shape'"'"'"\n"(2, 3)"\n"(9223372036854775807, 2)"\n'; return ;;
    io) printf '"#"\n","\n"D+"\n"d-"\n"3*"\n"\\xef\\xbb\\xbf"\n"\\x0d\\x0a"\n"\\x22"\n"nan"\n"\\x93NUMPY\\x01\\x00"\n"'"'"'<f8'"'"'"\n"True"\n"(2, 3)"\n'; return ;;
    test) files="src/cli/cmd_eqerr.c" ;;
    simulate|montecarlo|envfun) files="src/cli/cmd_$t.c $(ls src/cli/flight.c src/cli/cmd_envfun.c 2>/dev/null)" ;;
    *) files="src/cli/cmd_$t.c" ;;
    esac
    printf '"%%%% "\n'
    cat $files | grep -o '"-\{1,2\}[a-zA-Z][a-zA-Z0-9-]*"\|"[a-z][a-z0-9_]*"' | sort -u
}

# run TARGET CORPUS-DIR SECONDS LOG
run() {
    "$B/bin/fuzz_$1" -close_fd_mask=2 -max_len=4096 -timeout=20 -rss_limit_mb=2048 \
        -malloc_limit_mb=4096 -print_final_stats=1 -dict="$B/dict/$1.dict" \
        -artifact_prefix="$B/crashes/$1-" -max_total_time="$3" "$2" >"$4" 2>&1
}

export ASAN_OPTIONS=${ASAN_OPTIONS:-allocator_may_return_null=1:max_allocation_size_mb=1024}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export OPENBLAS_NUM_THREADS=1

mode=${1:-}
case $mode in
deps) deps; exit $? ;;
quick|long) secs=${2:-60} ;;
*) echo "usage: run.sh deps | quick SECONDS | long SECONDS" >&2; exit 64 ;;
esac

mkdir -p "$B/dict" "$B/crashes" "$B/logs" "$B/tmp" "$B/corpus" "$B/quick" || exit 1
TMPDIR=$(cd "$B/tmp" && pwd); export TMPDIR
total=0 fail=0 failed=""
for t in ${FUZZ_TARGETS:-}; do
    dict "$t" >"$B/dict/$t.dict"
    log="$B/logs/$t.log"
    if [ "$mode" = quick ]; then
        # each seed once, then a short run from the seeds
        if ! "$B/bin/fuzz_$t" -close_fd_mask=2 -runs=1 $SEEDS/$t/* >"$B/logs/$t.replay.log" 2>&1; then
            rm -rf "$TMPDIR"/igea-fuzz-*
            echo "fuzz_$t: a seed input fails (log: $B/logs/$t.replay.log)"
            tail -n 30 "$B/logs/$t.replay.log"
            fail=1 failed="$failed $t"
            continue
        fi
        nseed=$(ls $SEEDS/$t | wc -l)
        rm -rf "$B/quick/$t" && mkdir -p "$B/quick/$t" && cp $SEEDS/$t/* "$B/quick/$t/"
        corpus="$B/quick/$t"
    else
        nseed=0
        mkdir -p "$B/corpus/$t" && cp -n $SEEDS/$t/* "$B/corpus/$t/" 2>/dev/null
        corpus="$B/corpus/$t"
    fi
    run "$t" "$corpus" "$secs" "$log"
    st=$?
    # the private directories of targets that stopped at a failure
    rm -rf "$TMPDIR"/igea-fuzz-*
    n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    n=$(( ${n:-0} + nseed ))
    total=$((total + n))
    if [ $st -ne 0 ]; then
        fail=1 failed="$failed $t"
        echo "fuzz_$t: FAILED after $n executions (exit $st); log: $log"
        grep -m1 -A12 'ERROR\|igea-fuzz:\|runtime error' "$log" | head -n 24
        grep 'Test unit written to' "$log"
    else
        echo "fuzz_$t: $n executions in ${secs} s, no failure"
    fi
done
echo "fuzz ($mode): $total executions counted over the targets:${FUZZ_TARGETS:-}"
if [ $fail -ne 0 ]; then
    echo "fuzz: failures in:$failed (reproduce: $B/bin/fuzz_<target> <crash file>)"
    exit 1
fi
exit 0
