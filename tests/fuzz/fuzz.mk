# tests/fuzz/fuzz.mk - libFuzzer targets (clang): make fuzz
#
#   make fuzz        each target for FUZZ_TIME seconds (default 60), on a
#                    corpus kept in $(FUZZ_BUILD)/corpus (seeded from
#                    tests/fuzz/corpus, which stays small); crashes are saved
#                    in $(FUZZ_BUILD)/crashes/<target>-crash-<sha1>
#   make fuzz-quick  (part of make check) the seed corpus replayed, then each
#                    target for FUZZ_QUICK_TIME seconds (default 3)
#   make fuzz-deps   clang with libFuzzer, installed as root on Debian
#
# One target per reader (text, npy: whole, streamed, two-pass and piped reads
# agree bit for bit), one of the library's reader alone (io), and per command (cli_run in process: documented exit
# status, no file or temporary left by a failure, 74 when stdout is full);
# the input format and every check are in harness.h. Some targets longer:
#   make fuzz FUZZ_TARGETS="text npy" FUZZ_TIME=300
# The targets compile the library and the driver (without main.c) with
# clang -fsanitize=fuzzer,address,undefined. Reproduce a crash with
#   $(FUZZ_BUILD)/bin/fuzz_<target> $(FUZZ_BUILD)/crashes/<target>-crash-<sha1>
# (IGEA_FUZZ_TRACE=1 prints each run's command line and exit status).

FUZZ_CC         ?= clang
FUZZ_TIME       ?= 60
FUZZ_QUICK_TIME ?= 3
FUZZ_BUILD      ?= $(BUILD)/fuzz
FUZZ_TARGETS    := text npy eqerr test regress rls redund stability accel envfun simulate \
                   montecarlo io
FUZZ_SAN        := -fsanitize=address,undefined -fno-sanitize-recover=undefined \
                   -fno-omit-frame-pointer
FUZZ_CFLAGS     := -O1 -g $(FUZZ_SAN) -fsanitize=fuzzer-no-link -Isrc/cli -DIGEA_BUILDING
FUZZ_LIB_OBJ    := $(patsubst src/%.c,$(FUZZ_BUILD)/obj/lib/%.o,$(LIB_SRC))
FUZZ_CLI_OBJ    := $(patsubst src/cli/%.c,$(FUZZ_BUILD)/obj/cli/%.o,$(filter-out src/cli/main.c,$(CLI_SRC)))
FUZZ_BINS       := $(patsubst %,$(FUZZ_BUILD)/bin/fuzz_%,$(FUZZ_TARGETS))
FUZZ_RUN        = FUZZ_BUILD=$(FUZZ_BUILD) FUZZ_CC=$(FUZZ_CC) FUZZ_TARGETS="$(FUZZ_TARGETS)" \
                  sh tests/fuzz/run.sh

.PHONY: fuzz fuzz-quick fuzz-deps fuzz-bins
CHECK_EXTRA += fuzz-quick

fuzz-deps:
	@$(FUZZ_RUN) deps

fuzz-bins: $(FUZZ_BINS)

fuzz: fuzz-deps
	@$(MAKE) --no-print-directory fuzz-bins
	@$(FUZZ_RUN) long $(FUZZ_TIME)

fuzz-quick:
	@if $(FUZZ_RUN) deps; then \
	  $(MAKE) --no-print-directory fuzz-bins && $(FUZZ_RUN) quick $(FUZZ_QUICK_TIME); \
	else echo "fuzz-quick: skipped: no clang with libFuzzer, and it cannot be installed here"; fi

# The project's sources are not required to be free of clang-only warnings
# here; the harness is.
$(FUZZ_BUILD)/obj/lib/%.o: src/%.c $(HEADERS) | $(FUZZ_BUILD)/obj/lib
	$(FUZZ_CC) $(CPPFLAGS) $(filter-out -Werror,$(WARN)) $(FUZZ_CFLAGS) -c $< -o $@

$(FUZZ_BUILD)/obj/cli/%.o: src/cli/%.c $(wildcard src/cli/*.h) $(HEADERS) | $(FUZZ_BUILD)/obj/cli
	$(FUZZ_CC) $(CPPFLAGS) $(filter-out -Werror,$(WARN)) $(FUZZ_CFLAGS) -c $< -o $@

$(FUZZ_BUILD)/obj/%.o: tests/fuzz/%.c tests/fuzz/harness.h $(wildcard src/cli/*.h) $(HEADERS) | $(FUZZ_BUILD)/obj
	$(FUZZ_CC) $(CPPFLAGS) $(WARN) $(FUZZ_CFLAGS) -c $< -o $@

$(FUZZ_BINS): $(FUZZ_BUILD)/bin/fuzz_%: $(FUZZ_BUILD)/obj/fuzz_%.o $(FUZZ_BUILD)/obj/harness.o \
              $(FUZZ_LIB_OBJ) $(FUZZ_CLI_OBJ) | $(FUZZ_BUILD)/bin
	$(FUZZ_CC) -fsanitize=fuzzer,address,undefined -o $@ $^ $(LIBS)

$(FUZZ_BUILD)/obj $(FUZZ_BUILD)/obj/lib $(FUZZ_BUILD)/obj/cli $(FUZZ_BUILD)/bin:
	mkdir -p $@
