# tests/audit/audit.mk - generated invalid-argument and OOM suites, TSan
#
#   make audit   generate the tables from include/igea/*.h, build and run
#                the invalid-argument, out-of-memory and 8-thread suites,
#                and the first and last again under ASan + UBSan
#   make audit-asan   only the ASan + UBSan part
#   make tsan    the 8-thread suite under ThreadSanitizer (gcc)
#
# tests/audit/gen_invalid.py (system python3, standard library only) reads
# the public headers and tests/audit/baselines.py and writes the tables;
# it fails when an exported function has no baseline it can resolve.
# tests/audit/known_defects.txt lists the checks known to fail today.

AUDIT_DIR   := $(BUILD)/audit
AUDIT_GEN   := $(AUDIT_DIR)/audit_gen.c
AUDIT_KNOWN := tests/audit/known_defects.txt
AUDIT_DEPS  := tests/audit/audit.h $(AUDIT_GEN) tests/oom.h
AUDIT_BINS  := $(AUDIT_DIR)/test_invalid $(AUDIT_DIR)/test_oom $(AUDIT_DIR)/test_threads
AUDIT_THREADS_REPS ?= 50
TSAN_DIR    := $(BUILD)/tsan
ASAN_DIR    := $(BUILD)/audit-asan

.PHONY: audit audit-build audit-asan tsan

$(AUDIT_DIR) $(TSAN_DIR):
	mkdir -p $@

$(AUDIT_GEN): tests/audit/gen_invalid.py tests/audit/baselines.py $(wildcard include/igea/*.h) | $(AUDIT_DIR)
	python3 tests/audit/gen_invalid.py $@ $(AUDIT_DIR)/audit_list.txt

$(AUDIT_DIR)/test_%: tests/audit/test_%.c $(AUDIT_DEPS) $(STATIC) | $(AUDIT_DIR)
	$(CC) $(CPPFLAGS) -I$(AUDIT_DIR) -Itests/audit -Itests $(APPCFLAGS) $< -o $@ \
	  $(STATIC) $(LIBS) -lpthread -ldl $(LDFLAGS_EXTRA)

audit-build: $(AUDIT_BINS)

# OpenBLAS's own threads are not the library's: one per process, so the
# suites' threads are the only ones and results are reproducible.
audit: $(AUDIT_BINS)
	@fail=0; \
	$(MAKE) --no-print-directory audit-asan || fail=1; \
	echo "== $(AUDIT_DIR)/test_invalid"; \
	$(AUDIT_DIR)/test_invalid $(AUDIT_KNOWN) || fail=1; \
	echo "== $(AUDIT_DIR)/test_oom"; \
	OPENBLAS_NUM_THREADS=1 $(AUDIT_DIR)/test_oom $(AUDIT_KNOWN) || fail=1; \
	echo "== $(AUDIT_DIR)/test_threads"; \
	OPENBLAS_NUM_THREADS=1 $(AUDIT_DIR)/test_threads $(AUDIT_KNOWN) $(AUDIT_THREADS_REPS) || fail=1; \
	exit $$fail

# The invalid-argument and threads suites again with the library built
# under AddressSanitizer and UBSan (float-cast-overflow included), so an
# out-of-bounds write inside a call is a failure even when it corrupts
# nothing visible (the out-of-memory suite needs its own malloc: not here).
ASAN_FLAGS := -fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer \
              -fno-sanitize-recover=all
audit-asan: | $(AUDIT_DIR)
	@$(MAKE) --no-print-directory BUILD=$(ASAN_DIR) OPT=-O1 CFLAGS_EXTRA="$(ASAN_FLAGS)" \
	  LDFLAGS_EXTRA="$(ASAN_FLAGS)" $(ASAN_DIR)/audit/test_invalid $(ASAN_DIR)/audit/test_threads \
	  >$(AUDIT_DIR)/asan-build.log 2>&1 || { cat $(AUDIT_DIR)/asan-build.log; exit 1; }
	@fail=0; \
	echo "== $(ASAN_DIR)/audit/test_invalid (AddressSanitizer, UBSan)"; \
	ASAN_OPTIONS=detect_leaks=0 $(ASAN_DIR)/audit/test_invalid $(AUDIT_KNOWN) || fail=1; \
	echo "== $(ASAN_DIR)/audit/test_threads (AddressSanitizer, UBSan)"; \
	ASAN_OPTIONS=detect_leaks=0 OPENBLAS_NUM_THREADS=1 \
	  $(ASAN_DIR)/audit/test_threads $(AUDIT_KNOWN) 5 || fail=1; \
	exit $$fail

# ThreadSanitizer: the library and the threads suite built with
# -fsanitize=thread in their own tree (BUILD=$(TSAN_DIR)).
tsan:
	$(MAKE) --no-print-directory BUILD=$(TSAN_DIR) OPT=-O1 \
	  CFLAGS_EXTRA="-fsanitize=thread -fno-omit-frame-pointer" \
	  LDFLAGS_EXTRA="-fsanitize=thread" $(TSAN_DIR)/audit/test_threads
	TSAN_OPTIONS="halt_on_error=1 exitcode=66 $(TSAN_OPTIONS)" OPENBLAS_NUM_THREADS=1 \
	  $(TSAN_DIR)/audit/test_threads $(AUDIT_KNOWN) 10

CHECK_EXTRA += audit
