# tests/audit/audit.mk - generated invalid-argument and OOM suites, TSan
#
#   make audit   generate the tables from include/igea/*.h, build and run
#                the invalid-argument, out-of-memory and 8-thread suites
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

.PHONY: audit audit-build tsan

$(AUDIT_DIR) $(TSAN_DIR):
	mkdir -p $@

$(AUDIT_GEN): tests/audit/gen_invalid.py tests/audit/baselines.py $(wildcard include/igea/*.h) | $(AUDIT_DIR)
	python3 tests/audit/gen_invalid.py $@ $(AUDIT_DIR)/audit_list.txt

$(AUDIT_DIR)/test_%: tests/audit/test_%.c $(AUDIT_DEPS) $(STATIC) | $(AUDIT_DIR)
	$(CC) $(CPPFLAGS) -I$(AUDIT_DIR) -Itests/audit -Itests $(APPCFLAGS) $< -o $@ \
	  $(STATIC) $(LIBS) -lpthread $(LDFLAGS_EXTRA)

audit-build: $(AUDIT_BINS)

# OpenBLAS's own threads are not the library's: one per process, so the
# suites' threads are the only ones and results are reproducible.
audit: $(AUDIT_BINS)
	@fail=0; \
	echo "== $(AUDIT_DIR)/test_invalid"; \
	$(AUDIT_DIR)/test_invalid $(AUDIT_KNOWN) || fail=1; \
	echo "== $(AUDIT_DIR)/test_oom"; \
	OPENBLAS_NUM_THREADS=1 $(AUDIT_DIR)/test_oom $(AUDIT_KNOWN) || fail=1; \
	echo "== $(AUDIT_DIR)/test_threads"; \
	OPENBLAS_NUM_THREADS=1 $(AUDIT_DIR)/test_threads $(AUDIT_KNOWN) $(AUDIT_THREADS_REPS) || fail=1; \
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
