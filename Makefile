# csgtrace — build, dependencies, tests, demo, benchmarks.
#
#   make          build/csgtrace (optimised) and the test programs
#   make deps     install the missing Debian packages (root), or print the
#                 exact `sudo apt-get install ...` line (non-root)
#   make test     deps + build + every test (also under ASan + UBSan)
#   make demo     deps + build + render the showcase in both modes, compare
#   make bench    deps + build + the quick benchmark suite (bench/, ~5 min)
#   make bench-speed      one core against POV-Ray 3.7 (trace to trace) and
#                 Embree (primary rays): bench/vs_povray.sh, bench/vs_embree.sh
#   make bench-accuracy   the speed-versus-accuracy grid (bench/ACCURACY.md)
#   make bench-primary    the primary pass's throughput: both OpenCL kernel
#                 variants against the C worker (bench/primary_pass.sh)
#   make bench-full       the full suite and the accuracy grid (~45 min)
#   make bench-node       this node: serial, homo and hetero at np = 2, 4, ..
#                 its CPUs, tile 32 and 64, PNG and EXR (bench/NODE.md)
#   make install  build/csgtrace, its image module and its manual page under
#                 PREFIX (/usr/local): bin/, lib/csgtrace/, share/man/man1/;
#                 DESTDIR for staging; make uninstall removes them
#   make sim      build/sim/csgsim: the same master and worker built with
#                 SimGrid's SMPI, tiles replaced by measured costs (bench/sim/)
#   make bench-scale  the simulated 16..1024-worker grid (bench/SCALE.md)
#   make fuzz     libFuzzer over the whole pipeline for FUZZ_SECONDS (60)
#   make fuzz-seeds  the same fuzzer over its seeds only (what CI runs)
#   make clean
#
# The engine sources (flattening, tracing, shading) are compiled twice, once
# per precision (real = float, real = double with -DCSG_DOUBLE), into one
# program: --precision picks the table at run time (workers/engine.h).
#
# OpenImageIO is not linked into any program: host/output/image_oiio.cpp is built
# alone as the module build/csgtrace-image.so, which host/output/image_loader.c loads on
# the first image call that needs it (host/output/image_module.h).  A process that
# never reads an image nor writes one other than PNG or PPM (check, every MPI
# worker, a render to PNG or PPM: host/output/stream.c, zlib) never maps it.

DEB_PACKAGES := build-essential pkg-config openmpi-bin libopenmpi-dev \
	pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers clinfo \
	zlib1g-dev libzstd-dev libopenimageio-dev openimageio-tools povray povray-includes \
	libcmocka-dev gnuplot-nox python3 nettle-dev libfreetype-dev
# Only for the benchmarks: their reference programs (bench/embree_primary.c,
# Tachyon for bench/spd.sh) and POV-Ray's sample scenes (bench/povray_samples.sh).
BENCH_DEB_PACKAGES := libembree-dev tachyon-bin-nox povray-examples

CC := mpicc
CXX := g++
ROOT := $(abspath .)

WARN := -Wall -Wextra -Werror -Wshadow -Wundef -Wdouble-promotion \
	-Wstrict-prototypes -Wno-unused-function
# Bit-exact agreement with the OpenCL kernels: no contraction into FMA,
# IEEE semantics everywhere.
FPFLAGS := -ffp-contract=off -fno-fast-math -fexcess-precision=standard
DEFS := -D_GNU_SOURCE
OIIO_CFLAGS = $(shell pkg-config --cflags OpenImageIO 2>/dev/null)
OIIO_LIBS = $(shell pkg-config --libs OpenImageIO 2>/dev/null || echo -lOpenImageIO -lOpenImageIO_Util)

OPT ?= -O2
# The per-precision objects (the C engine: tracing, shading, pigments) at
# -O3 where the rest is at -O2: ~8-11% less CPU a ray on the paper scenes
# (bench/SPEED.md), the same bits (no contraction, no fast-math either way).
ENGINE_OPT ?= $(OPT:-O2=-O3)
# The BVH build too (csg/bvh_build.c): its box unions vectorise, ~30% fewer
# instructions building the hierarchy of 10^5 boxes, the same tree (#39).
BVH_OPT ?= $(OPT:-O2=-O3)
# TrueType fonts (text { ttf ... }: csg/lang/outline.c) through FreeType.
FT_CFLAGS = $(shell pkg-config --cflags freetype2 2>/dev/null || echo -I/usr/include/freetype2)
FT_LIBS = $(shell pkg-config --libs freetype2 2>/dev/null || echo -lfreetype)
CFLAGS_COMMON = -std=c11 $(WARN) $(FPFLAGS) $(DEFS) $(FT_CFLAGS) -g -MMD -MP
CXXFLAGS_COMMON = -std=c++17 -Wall -Wextra -Werror -g -MMD -MP -fPIC -fvisibility=hidden \
	$(OIIO_CFLAGS)
# PNG is written without the image module, with zlib (host/output/stream.c).
ZLIB_LIBS = $(shell pkg-config --libs zlib 2>/dev/null || echo -lz)
# 8-bit results compressed on the wire (--compress: comm/pixels_z.c).
ZSTD_LIBS = $(shell pkg-config --libs libzstd 2>/dev/null || echo -lzstd)
LDLIBS = -lOpenCL $(ZLIB_LIBS) $(ZSTD_LIBS) $(FT_LIBS) -lnettle -lpthread -lm
# The image module: everything it needs resolved at link time (-z defs).
MODULE_LDFLAGS = -shared -Wl,-z,defs -Wl,--as-needed
MODULE := csgtrace-image.so

SAN := -fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer \
	-fno-sanitize-recover=undefined,float-cast-overflow
SAN_HOOKS := $(SAN) -DCSG_TEST_HOOKS

# Sources: every .c of these folders; the engine ones get two objects each.
ENGINE_SRCS := csg/flatten.c csg/blob.c workers/shade.c workers/pigment.c workers/engine.c \
	workers/cost.c
ALL_C := $(wildcard csg/*.c csg/lang/*.c comm/*.c workers/*.c host/*.c host/pass/*.c \
	host/output/*.c) sim/tile_sim.c sim/page_trace.c
PLAIN_SRCS := $(filter-out $(ENGINE_SRCS) host/main.c,$(ALL_C))
MODULE_SRCS := host/output/image_oiio.cpp
TEST_SRCS := $(wildcard tests/test_*.c)

# $(call objs,BUILDDIR)
objs = $(PLAIN_SRCS:%.c=$(1)/obj/%.o) \
	$(ENGINE_SRCS:%.c=$(1)/obj/float/%.o) $(ENGINE_SRCS:%.c=$(1)/obj/double/%.o) \
	$(1)/obj/gen/kernel_source.o

B := build
BA := build/asan

# The test hooks (comm/test_hooks.h) exist only in test builds: each source
# that includes that header (directly: the list is its includers) is
# compiled a second time with -DCSG_TEST_HOOKS, into $(B)/hooks, for the
# test programs and build/csgtrace-test; build/csgtrace, the program that is
# installed, reads no CSGTRACE_TEST_* variable.  The ASan build is a test
# build throughout.
HOOKED_SRCS := $(shell grep -l '"[./]*comm/test_hooks\.h"\|"test_hooks\.h"' $(PLAIN_SRCS))
LIB_OBJS := $(call objs,$(B))
LIB_OBJS_TEST := $(filter-out $(HOOKED_SRCS:%.c=$(B)/obj/%.o),$(LIB_OBJS)) \
	$(HOOKED_SRCS:%.c=$(B)/hooks/%.o)
LIB_OBJS_ASAN := $(call objs,$(BA))
TEST_BINS := $(TEST_SRCS:tests/%.c=$(B)/tests/%)
TEST_BINS_ASAN := $(TEST_SRCS:tests/%.c=$(BA)/tests/%)

.PHONY: sim bench-scale deps-sim
.PHONY: all asan deps deps-bench test demo bench bench-full bench-accuracy bench-speed bench-primary bench-paging golden fuzz fuzz-seeds \
	bench-node \
	clean install uninstall
# (the harnesses that link the engine and the OpenCL pass too: an A/B that
# copies one after `make all` would otherwise time the old code)
BENCH_HARNESSES := $(addprefix $(B)/bench/,primary_rays primary_pass shadow_pass png_write \
	store_threads)
all: $(B)/csgtrace $(B)/csgtrace-test $(B)/$(MODULE) $(TEST_BINS) $(B)/tests/rogue_worker \
	$(B)/tests/progress_probe $(BENCH_HARNESSES)
asan: $(BA)/csgtrace $(BA)/$(MODULE) $(TEST_BINS_ASAN)


# ---- the OpenCL program's source, embedded ------------------------------------
# simd_kernels/primary.cl with its includes inlined, as a C string
# (tools/embed_kernels.py): the program reads no source tree at run time.
# build/gen/kernel_source.d lists the headers it was made from.
GEN := build/gen
$(GEN)/kernel_source.c: simd_kernels/primary.cl tools/embed_kernels.py
	@mkdir -p $(dir $@)
	python3 tools/embed_kernels.py $< $@ -I csg/device -I simd_kernels
$(B)/obj/gen/kernel_source.o: $(GEN)/kernel_source.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -c $< -o $@
$(BA)/obj/gen/kernel_source.o: $(GEN)/kernel_source.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN_HOOKS) -c $< -o $@

# ---- objects ---------------------------------------------------------------
$(B)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -c $< -o $@
$(B)/obj/csg/bvh_build.o: csg/bvh_build.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(BVH_OPT) -c $< -o $@
$(B)/obj/float/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(ENGINE_OPT) -c $< -o $@
$(B)/obj/double/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(ENGINE_OPT) -DCSG_DOUBLE -c $< -o $@
$(B)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS_COMMON) $(OPT) -c $< -o $@
$(B)/hooks/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -DCSG_TEST_HOOKS -c $< -o $@

$(BA)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN_HOOKS) -c $< -o $@
$(BA)/obj/float/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN_HOOKS) -c $< -o $@
$(BA)/obj/double/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN_HOOKS) -DCSG_DOUBLE -c $< -o $@
$(BA)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS_COMMON) -O1 $(SAN) -c $< -o $@

# ---- programs ----------------------------------------------------------------
# Every program needs its build's module at run time (order-only: a new
# module does not relink the programs).
$(B)/csgtrace: $(B)/obj/host/main.o $(LIB_OBJS) | $(B)/$(MODULE)
	$(CC) $^ -o $@ $(LDLIBS)
# The same program with the test hooks, for the end-to-end tests that use them.
$(B)/csgtrace-test: $(B)/obj/host/main.o $(LIB_OBJS_TEST) | $(B)/$(MODULE)
	$(CC) $^ -o $@ $(LDLIBS)
$(BA)/csgtrace: $(BA)/obj/host/main.o $(LIB_OBJS_ASAN) | $(BA)/$(MODULE)
	$(CC) $(SAN) $^ -o $@ $(LDLIBS)

$(B)/tests/%: $(B)/obj/tests/%.o $(LIB_OBJS_TEST) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS) -lcmocka
# Who must make MPI progress for a large message (tests/e2e_progress.sh).
$(B)/tests/progress_probe: $(B)/obj/tests/progress_probe.o $(LIB_OBJS_TEST) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)
# A worker that breaks the protocol on purpose (tests/e2e_mpi.sh).
$(B)/tests/rogue_worker: $(B)/obj/tests/rogue_worker.o $(LIB_OBJS_TEST) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)

$(BA)/tests/%: $(BA)/obj/tests/%.o $(LIB_OBJS_ASAN) | $(BA)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $(SAN) $^ -o $@ $(LDLIBS) -lcmocka

# The module converts 8-bit pixels with the program's own code
# (comm/pixels.c, compiled again position-independent).
$(B)/$(MODULE): $(MODULE_SRCS:%.cpp=$(B)/obj/%.o) $(B)/obj/pic/comm/pixels.o
	$(CXX) $(MODULE_LDFLAGS) $^ -o $@ $(OIIO_LIBS)
$(BA)/$(MODULE): $(MODULE_SRCS:%.cpp=$(BA)/obj/%.o) $(BA)/obj/pic/comm/pixels.o
	$(CXX) $(SAN) $(MODULE_LDFLAGS) $^ -o $@ $(OIIO_LIBS)
$(B)/obj/pic/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -fPIC -c $< -o $@
$(BA)/obj/pic/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN) -fPIC -c $< -o $@

# ---- the pipeline fuzzer (libFuzzer, clang) ----------------------------------------
# build/fuzz/fuzz_pipeline: every stage of a render on each input
# (tests/fuzz_pipeline.c), with ASan + UBSan; the dictionary is the lexer's
# own keyword table and the pattern and wave keywords (csg/device/patterns.h),
# the seeds are the example scenes and tests/fuzz_seeds/ (the inputs of
# past findings).  (Warnings are enforced by the gcc
# builds; clang's -Wdouble-promotion also flags libm macros, so the fuzz
# build only reports.)
F := build/fuzz
FUZZ_CC ?= clang-15
FUZZ_SECONDS ?= 60
FUZZ_SAN := -fsanitize=address,undefined,float-cast-overflow \
	-fno-sanitize-recover=undefined,float-cast-overflow -fno-omit-frame-pointer
FUZZ_CFLAGS = -std=c11 $(filter-out -Werror -Wdouble-promotion,$(WARN)) -ffp-contract=off -fno-fast-math $(DEFS) $(FT_CFLAGS) -g -O1 -MMD -MP $(FUZZ_SAN)
FUZZ_C := $(filter-out $(ENGINE_SRCS),$(wildcard csg/*.c csg/lang/*.c)) \
	workers/engine_common.c workers/tile.c workers/tile_run.c workers/pager.c workers/noise.c \
	comm/pixels.c comm/pixels_z.c \
	comm/tiles.c
FUZZ_OBJS := $(FUZZ_C:%.c=$(F)/obj/%.o) $(ENGINE_SRCS:%.c=$(F)/obj/float/%.o) \
	$(ENGINE_SRCS:%.c=$(F)/obj/double/%.o)

$(F)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -c $< -o $@
$(F)/obj/float/%.o: %.c
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -c $< -o $@
$(F)/obj/double/%.o: %.c
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -DCSG_DOUBLE -c $< -o $@
$(F)/fuzz_pipeline: $(F)/obj/tests/fuzz_pipeline.o $(FUZZ_OBJS)
	$(FUZZ_CC) $(FUZZ_SAN) -fsanitize=fuzzer $^ -o $@ $(ZLIB_LIBS) $(ZSTD_LIBS) $(FT_LIBS) -lm
$(F)/pov.dict: csg/lang/lexer.c csg/device/patterns.h
	@mkdir -p $(dir $@)
	sed -n 's/^ *{"\([a-z_0-9]*\)", CSG_KW_.*/"\1"/p' csg/lang/lexer.c >$@
	sed -n 's/^ *PATTERN([A-Z_]*, \([a-z_]*\),.*/"\1"/p; s/^ *X([A-Z_]*, \([a-z_]*\)).*/"\1_wave"/p' \
		csg/device/patterns.h >>$@
	sed -n '/^#define CSG_PATTERN_ALIASES/p' csg/device/patterns.h | \
		grep -o 'ALIAS([a-z_]*,' | sed 's/ALIAS(\(.*\),/"\1"/' >>$@
	printf '"#declare"\n"#include"\n"#version"\n"{"\n"}"\n"<"\n">"\n' >>$@

fuzz: deps $(F)/fuzz_pipeline $(F)/pov.dict
	@mkdir -p $(F)/corpus $(F)/seeds
	cp scenes/*.pov tests/fuzz_seeds/*.pov $(F)/seeds/
	$(F)/fuzz_pipeline -max_total_time=$(FUZZ_SECONDS) -max_len=4096 -timeout=10 \
		-dict=$(F)/pov.dict $(F)/corpus $(F)/seeds

# The fuzzer over its seeds alone, no fuzzing (.ci/run, after make test):
# the fuzzer still builds, and no past finding (tests/fuzz_seeds) is back.
fuzz-seeds: deps $(F)/fuzz_pipeline
	@mkdir -p $(F)/seeds
	cp scenes/*.pov tests/fuzz_seeds/*.pov $(F)/seeds/
	$(F)/fuzz_pipeline -runs=0 -max_len=4096 -timeout=10 $(F)/seeds

# Benchmark helpers (never part of csgtrace): the primary-pass timing
# harness over the engine, and the Embree reference it is compared with.
$(B)/bench/primary_rays: $(B)/obj/bench/primary_rays.o $(LIB_OBJS) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)
$(B)/bench/primary_pass: $(B)/obj/bench/primary_pass.o $(LIB_OBJS) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)
$(B)/bench/shadow_pass: $(B)/obj/bench/shadow_pass.o $(LIB_OBJS) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)
# The PNG writer's compression settings against the module's (bench/png_write.c).
$(B)/bench/png_write: $(B)/obj/bench/png_write.o $(LIB_OBJS) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)
# The store threads' throughput, one against several (bench/store_threads.c).
$(B)/bench/store_threads: $(B)/obj/bench/store_threads.o $(LIB_OBJS) | $(B)/$(MODULE)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)
# What --compress costs a worker and rank 0 (bench/compress_tiles.c).
$(B)/bench/compress_tiles: $(B)/obj/bench/compress_tiles.o $(B)/obj/comm/pixels_z.o
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(ZSTD_LIBS)
# A nap's CPU time, what the simulation charges for it (bench/nap_cost.c).
$(B)/bench/nap_cost: $(B)/obj/bench/nap_cost.o
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ -lpthread
$(B)/bench/embree_primary: bench/embree_primary.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) $< -o $@ -lembree3 -lm

# ---- the simulated build (SimGrid SMPI) -----------------------------------------
# The project's own master, scheduler, link and worker compiled with smpicc;
# what differs: tile_run_rect (sim/tile_run.c for workers/tile_run.c), the driver
# (sim/main.c) and the link-time stubs (sim/stubs.c).  Not part of
# `make test`'s build: SimGrid is only needed here (make deps-sim).
S := build/sim
SIM_CC := smpicc
SIM_SRCS := $(filter-out host/main.c host/render.c host/compare.c host/cli.c host/feed.c \
	host/pass/ocl.c host/pass/pass.c host/pass/cl_cache.c workers/tile_run.c $(ENGINE_SRCS), \
	$(ALL_C)) sim/main.c sim/stubs.c sim/tile_run.c
SIM_OBJS := $(SIM_SRCS:%.c=$(S)/obj/%.o) $(ENGINE_SRCS:%.c=$(S)/obj/float/%.o) \
	$(ENGINE_SRCS:%.c=$(S)/obj/double/%.o)

$(S)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(SIM_CC) $(CFLAGS_COMMON) $(OPT) -c $< -o $@
$(S)/obj/float/%.o: %.c
	@mkdir -p $(dir $@)
	$(SIM_CC) $(CFLAGS_COMMON) $(OPT) -c $< -o $@
$(S)/obj/double/%.o: %.c
	@mkdir -p $(dir $@)
	$(SIM_CC) $(CFLAGS_COMMON) -DCSG_DOUBLE $(OPT) -c $< -o $@
$(S)/csgsim: $(SIM_OBJS)
	$(SIM_CC) $^ -o $@ -Wl,--wrap=sem_clockwait,--wrap=atexit $(ZLIB_LIBS) $(ZSTD_LIBS) $(FT_LIBS) -lm

deps-sim:
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="libsimgrid-dev"

sim: deps-sim
	$(MAKE) $(S)/csgsim

bench-scale: sim $(B)/csgtrace
	bench/scale.sh

# ---- dependencies --------------------------------------------------------------
deps-bench:
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="$(BENCH_DEB_PACKAGES)"

deps:
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -z "$$missing" ]; then echo "deps: every package is installed"; \
	elif [ "$$(id -u)" = 0 ]; then \
	  echo "deps: installing$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq$$missing; \
	else \
	  echo "deps: missing Debian packages; as root, run:"; \
	  echo "  sudo apt-get update && sudo apt-get install$$missing"; exit 1; \
	fi

# ---- test, demo, bench -----------------------------------------------------------
test: deps
	$(MAKE) -j$$(nproc) all asan
	tests/run.sh

demo: deps
	$(MAKE) $(B)/csgtrace
	scenes/demo.sh

bench: deps
	$(MAKE) $(B)/csgtrace
	bench/run.sh --quick

# One core, trace to trace, against POV-Ray 3.7 (+WT1) on the six paper
# scenes, and primary rays against Embree (bench/SPEED.md).
bench-speed: deps deps-bench
	$(MAKE) $(B)/csgtrace $(B)/bench/primary_rays $(B)/bench/embree_primary
	bench/vs_povray.sh
	bench/vs_embree.sh
	python3 bench/speed_report.py bench/results -o bench/SPEED.md

bench-full: deps
	$(MAKE) $(B)/csgtrace
	bench/run.sh --full
	bench/accuracy.sh

# One node as a user runs it: speed-up, efficiency, busy, write tail.
bench-node: deps
	$(MAKE) $(B)/csgtrace
	python3 bench/node.py

# The primary pass in Mrays/s per core: packet and scalar kernels against the
# C worker's primary rays, N = 10 .. 10^4 spheres (bench/results/primary_pass).
bench-primary: deps
	$(MAKE) $(B)/csgtrace $(B)/bench/primary_pass $(B)/bench/shadow_pass
	bench/primary_pass.sh
	bench/shadow_pass.sh

# A worker's scene below a memory budget (--scene-memory): the budget swept
# from the whole scene to 1/64 of it on the SPD's tetra9 (bench/PAGING.md).
bench-paging: deps
	$(MAKE) $(B)/csgtrace
	bench/paging.sh

# Speed versus accuracy (issue 6): every knob against a reference render.
bench-accuracy: deps
	$(MAKE) $(B)/csgtrace
	bench/accuracy.sh

# New golden images for tests/test_golden.c (look at them before committing).
golden: $(B)/csgtrace
	@for s in scenes/*.pov; do n=$$(basename $$s .pov); \
	  $(B)/csgtrace render $$s -o tests/golden/$$n.png --width 160 --height 120 || exit 1; done

# ---- installation ------------------------------------------------------------------
# The program needs nothing of the source tree: its OpenCL source is built
# in, and it finds its image module in ../lib/csgtrace/ (host/output/
# image_loader.c).  The manual page is --help's text (tools/man_page.py).
PREFIX ?= /usr/local
$(B)/csgtrace.1: $(B)/csgtrace tools/man_page.py | $(B)/$(MODULE)
	python3 tools/man_page.py $(B)/csgtrace >$@.tmp && mv $@.tmp $@
install: $(B)/csgtrace $(B)/$(MODULE) $(B)/csgtrace.1
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib/csgtrace \
		$(DESTDIR)$(PREFIX)/share/man/man1
	install -m 755 $(B)/csgtrace $(DESTDIR)$(PREFIX)/bin/csgtrace
	install -m 644 $(B)/$(MODULE) $(DESTDIR)$(PREFIX)/lib/csgtrace/$(MODULE)
	install -m 644 $(B)/csgtrace.1 $(DESTDIR)$(PREFIX)/share/man/man1/csgtrace.1
uninstall:
	rm -f $(DESTDIR)$(PREFIX)/bin/csgtrace $(DESTDIR)$(PREFIX)/lib/csgtrace/$(MODULE) \
		$(DESTDIR)$(PREFIX)/share/man/man1/csgtrace.1
	-rmdir $(DESTDIR)$(PREFIX)/lib/csgtrace 2>/dev/null

clean:
	rm -rf build

-include $(shell find build -name '*.d' 2>/dev/null)
