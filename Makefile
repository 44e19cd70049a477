# rodsim: plain Makefile. `make demo` and `make test` are the README's two commands;
# both first install any missing Debian package (see `make deps`).

CC      ?= cc
PKGS    := osmesa libpng freetype2 libavcodec libavformat libswscale libavutil lapacke
DEBS    := build-essential pkg-config libosmesa6-dev libpng-dev libfreetype-dev fonts-dejavu-core \
           libavcodec-dev libavformat-dev libswscale-dev libavutil-dev liblapacke-dev liblapack-dev \
           libblas-dev clang libclang-rt-dev
WARN    := -Wall -Wextra -Wpedantic -Wshadow -Wmissing-prototypes
CFLAGS  ?= -O3 -g
ALL_CFLAGS = -std=c11 -D_DEFAULT_SOURCE $(WARN) $(CFLAGS) $(EXTRA_CFLAGS) -Iinclude \
             $(shell pkg-config --cflags $(PKGS) 2>/dev/null) -DRODSIM_SOURCE_DIR='"$(CURDIR)"'
LDLIBS  = $(shell pkg-config --libs $(PKGS) 2>/dev/null) -llapack -lblas -lpthread -lm
LDFLAGS ?=

# Build flavours: release (default) and asan (AddressSanitizer + UBSan).
BUILD   ?= build/release
SAN_FLAGS := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined

# One folder per layer (README "Layout"): src/LAYER/NAME.c, include/LAYER/NAME.h,
# tests/LAYER/test_NAME.c; benchmarks in tests/bench/.
SRC     := $(wildcard src/*/*.c)
HEADERS := $(wildcard include/*/*.h)
LIB_OBJ := $(patsubst src/%.c,$(BUILD)/obj/%.o,$(filter-out src/cli/main.c,$(SRC)))
TESTS   := $(filter-out tests/bench/%,$(wildcard tests/*/test_*.c))
TEST_BIN:= $(patsubst tests/%.c,$(BUILD)/tests/%,$(TESTS))
BENCHES := $(wildcard tests/bench/bench_*.c)
BENCH_BIN := $(patsubst tests/%.c,$(BUILD)/tests/%,$(BENCHES))

.PHONY: all deps rodsim tests test test-release test-asan fuzz fuzzers demo bench figures readme clean
.DEFAULT_GOAL := all

all: rodsim

rodsim: $(BUILD)/rodsim
	@ln -sf $(BUILD)/rodsim rodsim

$(BUILD)/rodsim: $(BUILD)/obj/cli/main.o $(BUILD)/librodsim.a
	$(CC) $(ALL_CFLAGS) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/librodsim.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/obj/%.o: src/%.c $(HEADERS) Makefile
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/tests/%: tests/%.c $(wildcard tests/*.h) $(BUILD)/librodsim.a $(BUILD)/rodsim
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -Itests -DRODSIM_BIN='"$(CURDIR)/$(BUILD)/rodsim"' $(LDFLAGS) -o $@ $< $(BUILD)/librodsim.a $(LDLIBS)

tests: $(TEST_BIN)

# Installs the Debian packages that are missing (root, or sudo when not root).
deps:
	@missing=""; for p in $(DEBS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "rodsim: installing missing Debian packages:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null \
	    || { echo "rodsim: apt-get install failed for:$$missing" >&2; exit 1; }; \
	fi

# The README's test command: every test, in the release build and under ASan+UBSan.
test: deps
	@sh tests/run_all.sh

test-release:
	@$(MAKE) --no-print-directory BUILD=build/release tests rodsim
	@sh tests/run_tests.sh build/release

test-asan:
	@$(MAKE) --no-print-directory BUILD=build/asan CFLAGS="$(SAN_FLAGS)" LDFLAGS="-fsanitize=address,undefined" tests
	@sh tests/run_tests.sh build/asan

# Fuzzing (make test runs it): each parser's libFuzzer harness, tests/fuzz/fuzz_NAME.c,
# runs FUZZ_SECONDS on a copy of tests/fuzz/corpus/NAME/ under ASan + UBSan. The
# library is built with clang into build/fuzz (coverage for libFuzzer); clang and its
# libFuzzer come from the Debian packages clang and libclang-rt-dev (DEBS).
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

bench: deps
	@$(MAKE) --no-print-directory BUILD=build/release rodsim $(patsubst tests/%.c,build/release/tests/%,$(BENCHES))
	@for b in $(patsubst tests/%.c,build/release/tests/%,$(BENCHES)); do $$b || exit 1; done

demo: deps
	@$(MAKE) --no-print-directory BUILD=build/release rodsim
	@sh tests/demo.sh

# The thesis' figures into out/figures/, every point of every figure in parallel
# (one process per point, as many at once as there are cores).
figures: deps
	@$(MAKE) --no-print-directory BUILD=build/release rodsim
	./rodsim figure all --out out/figures

# Rewrites the README's generated blocks (command reference, scene keys) from
# the program's own output; tests/cli/test_readme.c fails when they differ.
readme:
	@$(MAKE) --no-print-directory BUILD=build/release rodsim
	@sh tests/readme.sh update build/release/rodsim README.md

clean:
	rm -rf build rodsim
