# rodsim: plain Makefile. `make demo` and `make test` are the README's two commands;
# each first installs the missing Debian packages it needs (DEBS_DEMO, + DEBS_TEST).

CC      ?= cc
# Headers of every package; the binary links only LINK_PKGS: EGL, OSMesa and
# libav* are opened at run time when something is drawn (gl_context.c,
# video.c; ~40 ms of every start otherwise). TEST_PKGS: tests that decode video.
PKGS    := egl osmesa libpng freetype2 fontconfig libavcodec libavformat libswscale libavutil lapacke
LINK_PKGS := libpng freetype2 fontconfig lapacke
TEST_PKGS := libavcodec libavformat libswscale libavutil
# Debian packages, by the target that needs them (README: "Dependencies and
# why each is there"; tests/cli/test_deps.c checks the two agree).
# DEBS_DEMO: building and rendering (make, make demo, make figures, make bench).
# libegl-dev (EGL headers, glvnd's libEGL.so.1), libegl-mesa0 (Mesa's EGL
# driver) and libgl1-mesa-dri (its llvmpipe, swrast_dri.so): the EGL backend;
# libosmesa6-dev: the OSMesa one; libfontconfig-dev: finds DejaVu Sans;
# libsuitesparse-dev: CHOLMOD, the tissue's sparse Cholesky (-lcholmod: no pkg-config file).
DEBS_DEMO := build-essential pkg-config libegl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev \
           libpng-dev libfreetype-dev libfontconfig-dev fonts-dejavu-core libavcodec-dev \
           libavformat-dev libswscale-dev libavutil-dev liblapacke-dev liblapack-dev libblas-dev \
           libsuitesparse-dev
# DEBS_TEST: what make test adds. clang, libclang-rt-dev: the fuzz run;
# libxml2-utils (xmllint), parallel (GNU parallel), snakemake and slurm-wlm:
# tests/cli/test_sweep.c parses the sweep's SVG, runs its --print-commands lines under GNU
# parallel, its --snakefile under Snakemake and its --sbatch array under a one-node Slurm
# it starts (slurmctld + slurmd, as root). python3 and the rest: python/rodsim, its
# tests (tests/python), the examples' plots, `pip install ./python` offline in a venv,
# make bench's bench_api (make bench installs this list too).
DEBS_TEST := clang libclang-rt-dev libxml2-utils parallel snakemake slurm-wlm python3 \
           python3-numpy python3-pytest python3-matplotlib python3-setuptools python3-pip \
           python3-venv
WARN    := -Wall -Wextra -Wpedantic -Wshadow -Wmissing-prototypes
CFLAGS  ?= -O3 -g
# -fPIC: one set of objects makes both the program (librodsim.a) and the
# shared library (librodsim.so); -fno-semantic-interposition keeps calls
# inside the library direct (inlined as without -fPIC), and the library
# exports only rodsim_* (src/api/rodsim.map).
PIC     := -fPIC -fno-semantic-interposition
ALL_CFLAGS = -std=c11 -D_DEFAULT_SOURCE $(WARN) $(PIC) $(CFLAGS) $(EXTRA_CFLAGS) -Iinclude \
             $(shell pkg-config --cflags $(PKGS) 2>/dev/null)
LDLIBS  = $(shell pkg-config --libs $(LINK_PKGS) 2>/dev/null) -lcholmod -llapack -lblas -ldl -lpthread -lm
TEST_LDLIBS = $(shell pkg-config --libs $(TEST_PKGS) 2>/dev/null)
LDFLAGS ?=

# The shared library: librodsim.so.MAJOR.MINOR, soname librodsim.so.MAJOR
# (MAJOR, MINOR: include/rodsim.h's RODSIM_API_VERSION_*).
SO_MAJOR := $(shell sed -n 's/^\#define RODSIM_API_VERSION_MAJOR \([0-9]*\).*/\1/p' include/rodsim.h)
SO_MINOR := $(shell sed -n 's/^\#define RODSIM_API_VERSION_MINOR \([0-9]*\).*/\1/p' include/rodsim.h)

# Build flavours: release (default) and asan (AddressSanitizer + UBSan).
BUILD   ?= build/release
# -fno-var-tracking: no location lists for variables in the debug
# information (what a debugger shows of a variable in optimized code);
# the machine code is the same, and the sanitizers' reports keep their
# file:line and inlined frames (the line tables). Without it GCC compiles
# the library 15 % and the tests 18 % faster under the sanitizers, the
# tests 10 % in release: make test's ASan build, and every test binary
# (TEST_CFLAGS), compile without it; the release library keeps it.
SAN_FLAGS := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined \
             -fno-var-tracking
TEST_CFLAGS := -fno-var-tracking
# The test binaries link with GNU gold where the compiler can use it
# (binutils has it on Debian 12): each links the whole static librodsim.a
# with its debug information, 0.5-0.9 CPU s with ld.bfd under the
# sanitizers, 0.03-0.3 with gold. The program and librodsim.so keep ld.bfd.
TEST_LDFLAGS := $(shell $(CC) -fuse-ld=gold -Wl,--version >/dev/null 2>&1 && echo -fuse-ld=gold)

# One folder per layer (README "Layout"): src/LAYER/[ROOM/]NAME.c,
# include/LAYER/[ROOM/]NAME.h, tests/LAYER/test_NAME.c; benchmarks in tests/bench/.
SRC     := $(shell find src -name '*.c' | sort)
HEADERS := $(shell find include -name '*.h' | sort)
LIB_OBJ := $(patsubst src/%.c,$(BUILD)/obj/%.o,$(filter-out src/cli/main.c,$(SRC))) \
           $(BUILD)/obj/gen/embedded.o
# Files compiled into the binary (include/base/embedded.h): the program reads
# nothing from the source tree at run time, so an installed or moved binary works.
EMBEDDED:= $(sort $(wildcard shaders/*.vert shaders/*.frag)) scenes/impulse.ini \
          scenes/buckling_figure.ini scenes/twist_figure.ini scenes/table2_450nN.ini
TESTS   := $(filter-out tests/bench/% tests/fuzz/%,$(shell find tests -name 'test_*.c' | sort))
TEST_BIN:= $(patsubst tests/%.c,$(BUILD)/tests/%,$(TESTS))
BENCHES := $(wildcard tests/bench/bench_*.c)
BENCH_BIN := $(patsubst tests/%.c,$(BUILD)/tests/%,$(BENCHES))

.PHONY: all deps deps-demo deps-test lib rodsim tests test test-release test-asan build-release build-asan fuzz fuzzers demo bench figures readme install clean
.DEFAULT_GOAL := all

all: rodsim lib

# librodsim.so (and its soname link) in $(BUILD), for C programs and python/rodsim.
lib: $(BUILD)/librodsim.so

rodsim: $(BUILD)/rodsim
	@ln -sf $(BUILD)/rodsim rodsim

$(BUILD)/rodsim: $(BUILD)/obj/cli/main.o $(BUILD)/librodsim.a
	$(CC) $(ALL_CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/librodsim.so: $(LIB_OBJ) src/api/rodsim.map
	$(CC) -shared -Wl,-soname,librodsim.so.$(SO_MAJOR) -Wl,--version-script=src/api/rodsim.map \
	  $(LDFLAGS) -o $@.$(SO_MAJOR).$(SO_MINOR) $(LIB_OBJ) $(LDLIBS)
	ln -sf librodsim.so.$(SO_MAJOR).$(SO_MINOR) $@.$(SO_MAJOR)
	ln -sf librodsim.so.$(SO_MAJOR).$(SO_MINOR) $@

$(BUILD)/librodsim.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/obj/%.o: src/%.c $(HEADERS) Makefile
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

# embedded.c: one array per file (its bytes in hex, by od, then a '\0') and
# the table of them; plain POSIX tools, no xxd.
$(BUILD)/gen/embedded.c: $(EMBEDDED) Makefile
	@mkdir -p $(dir $@)
	@{ echo '/* Generated by the Makefile from $(EMBEDDED): do not edit. */'; \
	  echo '#include "base/embedded.h"'; \
	  for f in $(EMBEDDED); do \
	    echo "static const unsigned char $$(echo "$$f" | tr -c 'A-Za-z0-9\n' '_')[] = {"; \
	    od -An -v -tx1 "$$f" | sed 's/ \([0-9a-f][0-9a-f]\)/0x\1,/g'; \
	    echo '0x00};'; \
	  done; \
	  echo 'const embedded_file embedded_files[] = {'; \
	  for f in $(EMBEDDED); do \
	    id=$$(echo "$$f" | tr -c 'A-Za-z0-9\n' '_'); \
	    echo "    {\"$$f\", $$id, sizeof $$id - 1},"; \
	  done; \
	  echo '    {0, 0, 0}};'; } >$@.tmp && mv $@.tmp $@

$(BUILD)/obj/gen/%.o: $(BUILD)/gen/%.c $(HEADERS) Makefile
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

# Tests (not the program) may read the source tree: RODSIM_SOURCE_DIR.
$(BUILD)/tests/%: tests/%.c $(wildcard tests/*.h) $(BUILD)/librodsim.a $(BUILD)/rodsim
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(TEST_CFLAGS) -Itests -DRODSIM_SOURCE_DIR='"$(CURDIR)"' -DRODSIM_BIN='"$(CURDIR)/$(BUILD)/rodsim"' $(LDFLAGS) $(TEST_LDFLAGS) -o $@ $< $(BUILD)/librodsim.a $(TEST_LDLIBS) $(LDLIBS)

tests: $(TEST_BIN)

# The example client of rodsim live (not a test): test_live runs it.
$(BUILD)/tests/cli/test_live: $(BUILD)/tests/live_driver

# Install the Debian packages that are missing (root, or sudo when not root);
# when they cannot be installed, one line names each missing package.
deps-demo:
	@sh tests/deps.sh demo $(DEBS_DEMO)

deps-test:
	@sh tests/deps.sh test $(DEBS_DEMO) $(DEBS_TEST)

deps: deps-test

# The README's test command: every test, in the release build and under ASan+UBSan.
test: deps-test
	@sh tests/run_all.sh

# build-FLAVOUR builds what test-FLAVOUR runs (tests/run_all.sh times the two apart).
build-release:
	@$(MAKE) --no-print-directory BUILD=build/release tests rodsim lib

test-release: build-release
	@sh tests/run_tests.sh build/release

build-asan:
	@$(MAKE) --no-print-directory BUILD=build/asan CFLAGS="$(SAN_FLAGS)" LDFLAGS="-fsanitize=address,undefined" tests

test-asan: build-asan
	@sh tests/run_tests.sh build/asan

# Fuzzing (make test runs it): each parser's libFuzzer harness, tests/fuzz/fuzz_NAME.c,
# runs FUZZ_SECONDS on a copy of tests/fuzz/corpus/NAME/ under ASan + UBSan. The
# library is built with clang into build/fuzz (coverage for libFuzzer); clang and its
# libFuzzer come from the Debian packages clang and libclang-rt-dev (DEBS_TEST).
FUZZ_SECONDS ?= 30
FUZZ_CFLAGS := -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer \
               -fno-sanitize-recover=undefined
FUZZERS := $(patsubst tests/fuzz/%.c,build/fuzz/bin/%,$(wildcard tests/fuzz/fuzz_*.c))

fuzzers:
	@$(MAKE) --no-print-directory BUILD=build/fuzz CC=clang CFLAGS="$(FUZZ_CFLAGS)" \
	  LDFLAGS="-fsanitize=address,undefined" build/fuzz/librodsim.a $(FUZZERS)

build/fuzz/bin/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz.h build/fuzz/librodsim.a
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -Itests/fuzz -fsanitize=fuzzer,address,undefined -o $@ $< \
	  build/fuzz/librodsim.a $(LDLIBS)

fuzz: fuzzers
	@sh tests/fuzz/run_fuzz.sh build/fuzz $(FUZZ_SECONDS)

bench: deps-test
	@$(MAKE) --no-print-directory BUILD=build/release rodsim lib $(patsubst tests/%.c,build/release/tests/%,$(BENCHES))
	@for b in $(patsubst tests/%.c,build/release/tests/%,$(BENCHES)); do $$b || exit 1; done

demo: deps-demo
	@$(MAKE) --no-print-directory BUILD=build/release rodsim
	@sh tests/demo.sh

# The thesis' figures into out/figures/, every point of every figure in parallel
# (one process per point, as many at once as there are cores).
figures: deps-demo
	@$(MAKE) --no-print-directory BUILD=build/release rodsim
	./rodsim figure all --out out/figures

# Rewrites the README's generated blocks (command reference, scene keys) from
# the program's own output; tests/cli/test_readme.c fails when they differ.
readme:
	@$(MAKE) --no-print-directory BUILD=build/release rodsim
	@sh tests/readme.sh update build/release/rodsim README.md
	@sh tests/readme.sh update build/release/rodsim docs/commands.md
	@sh tests/readme.sh update build/release/rodsim docs/scene-keys.md

# make install [PREFIX=/usr/local] [DESTDIR=staging]: the binary (shaders
# compiled in) and the scenes as examples in PREFIX/share/rodsim/scenes; the
# library: PREFIX/lib/librodsim.so.MAJOR.MINOR with its links, the header
# PREFIX/include/rodsim.h and PREFIX/lib/pkgconfig/rodsim.pc.
PREFIX  ?= /usr/local
LIBDIR  ?= $(PREFIX)/lib
install:
	@$(MAKE) --no-print-directory BUILD=build/release build/release/rodsim build/release/librodsim.so
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/rodsim/scenes
	install -m 755 build/release/rodsim $(DESTDIR)$(PREFIX)/bin/rodsim
	install -m 644 scenes/*.ini scenes/*.csv scenes/*.stl $(DESTDIR)$(PREFIX)/share/rodsim/scenes
	install -d $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(PREFIX)/include
	install -m 755 build/release/librodsim.so.$(SO_MAJOR).$(SO_MINOR) $(DESTDIR)$(LIBDIR)/
	ln -sf librodsim.so.$(SO_MAJOR).$(SO_MINOR) $(DESTDIR)$(LIBDIR)/librodsim.so.$(SO_MAJOR)
	ln -sf librodsim.so.$(SO_MAJOR).$(SO_MINOR) $(DESTDIR)$(LIBDIR)/librodsim.so
	install -m 644 include/rodsim.h $(DESTDIR)$(PREFIX)/include/rodsim.h
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' \
	  -e 's|@VERSION@|$(SO_MAJOR).$(SO_MINOR)|' src/api/rodsim.pc.in \
	  >$(DESTDIR)$(LIBDIR)/pkgconfig/rodsim.pc
	@# the loader's cache, so librodsim.so.1 is found (python/rodsim, clients)
	@if [ -z "$(DESTDIR)" ] && [ "$$(id -u)" = 0 ]; then ldconfig; fi

clean:
	rm -rf build rodsim
