# csgtrace — build, dependencies, tests, demo, benchmarks.
#
#   make          build/csgtrace (optimised) and the test programs
#   make deps     install the missing Debian packages (root), or print the
#                 exact `sudo apt-get install ...` line (non-root)
#   make test     deps + build + every test (also under ASan + UBSan)
#   make demo     deps + build + render the showcase in both modes, compare
#   make bench    deps + build + the quick benchmark suite (bench/, ~3 min)
#   make bench-accuracy   the speed-versus-accuracy grid (bench/ACCURACY.md)
#   make bench-primary    the primary pass's throughput: both OpenCL kernel
#                 variants against the C worker (bench/primary_pass.sh)
#   make bench-full       the full suite and the accuracy grid (~25 min)
#   make clean
#
# The engine sources (flattening, tracing, shading) are compiled twice, once
# per precision (real = float, real = double with -DCSG_DOUBLE), into one
# program: --precision picks the table at run time (workers/engine.h).

DEB_PACKAGES := build-essential pkg-config openmpi-bin libopenmpi-dev \
	pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers clinfo \
	libopenimageio-dev openimageio-tools povray povray-includes \
	libcmocka-dev gnuplot-nox python3

CC := mpicc
CXX := g++
ROOT := $(abspath .)

WARN := -Wall -Wextra -Werror -Wshadow -Wundef -Wdouble-promotion \
	-Wstrict-prototypes -Wno-unused-function
# Bit-exact agreement with the OpenCL kernels: no contraction into FMA,
# IEEE semantics everywhere.
FPFLAGS := -ffp-contract=off -fno-fast-math -fexcess-precision=standard
DEFS := -D_GNU_SOURCE -DCSG_SOURCE_DIR='"$(ROOT)"'
OIIO_CFLAGS = $(shell pkg-config --cflags OpenImageIO 2>/dev/null)
OIIO_LIBS = $(shell pkg-config --libs OpenImageIO 2>/dev/null || echo -lOpenImageIO -lOpenImageIO_Util)

OPT ?= -O2
CFLAGS_COMMON = -std=c11 $(WARN) $(FPFLAGS) $(DEFS) -g -MMD -MP
CXXFLAGS_COMMON = -std=c++17 -Wall -Wextra -Werror -g -MMD -MP $(OIIO_CFLAGS)
LDLIBS = $(OIIO_LIBS) -lOpenCL -lstdc++ -lm

SAN := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined

# Sources: every .c of these folders; the engine ones get two objects each.
ENGINE_SRCS := csg/flatten.c csg/blob.c workers/shade.c workers/engine.c
ALL_C := $(wildcard csg/*.c csg/lang/*.c host/*.c workers/*.c scenes/*.c)
PLAIN_SRCS := $(filter-out $(ENGINE_SRCS) host/main.c,$(ALL_C))
CXX_SRCS := $(wildcard host/*.cpp)
TEST_SRCS := $(wildcard tests/test_*.c)

# $(call objs,BUILDDIR)
objs = $(PLAIN_SRCS:%.c=$(1)/obj/%.o) $(CXX_SRCS:%.cpp=$(1)/obj/%.o) \
	$(ENGINE_SRCS:%.c=$(1)/obj/float/%.o) $(ENGINE_SRCS:%.c=$(1)/obj/double/%.o)

B := build
BA := build/asan

LIB_OBJS := $(call objs,$(B))
LIB_OBJS_ASAN := $(call objs,$(BA))
TEST_BINS := $(TEST_SRCS:tests/%.c=$(B)/tests/%)
TEST_BINS_ASAN := $(TEST_SRCS:tests/%.c=$(BA)/tests/%)

.PHONY: all asan deps test demo bench bench-full bench-accuracy bench-primary golden clean
all: $(B)/csgtrace $(TEST_BINS)
asan: $(BA)/csgtrace $(TEST_BINS_ASAN)

# ---- objects ---------------------------------------------------------------
$(B)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -c $< -o $@
$(B)/obj/float/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -c $< -o $@
$(B)/obj/double/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) $(OPT) -DCSG_DOUBLE -c $< -o $@
$(B)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS_COMMON) $(OPT) -c $< -o $@

$(BA)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN) -c $< -o $@
$(BA)/obj/float/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN) -c $< -o $@
$(BA)/obj/double/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_COMMON) -O1 $(SAN) -DCSG_DOUBLE -c $< -o $@
$(BA)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS_COMMON) -O1 $(SAN) -c $< -o $@

# ---- programs ----------------------------------------------------------------
$(B)/csgtrace: $(B)/obj/host/main.o $(LIB_OBJS)
	$(CC) $^ -o $@ $(LDLIBS)
$(BA)/csgtrace: $(BA)/obj/host/main.o $(LIB_OBJS_ASAN)
	$(CC) $(SAN) $^ -o $@ $(LDLIBS)

$(B)/tests/%: $(B)/obj/tests/%.o $(LIB_OBJS)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS) -lcmocka
$(BA)/tests/%: $(BA)/obj/tests/%.o $(LIB_OBJS_ASAN)
	@mkdir -p $(dir $@)
	$(CC) $(SAN) $^ -o $@ $(LDLIBS) -lcmocka

# Benchmark helpers (never part of csgtrace): the primary pass's throughput,
# OpenCL variants against the C worker (bench/primary_pass.sh).
$(B)/bench/primary_pass: $(B)/obj/bench/primary_pass.o $(LIB_OBJS)
	@mkdir -p $(dir $@)
	$(CC) $^ -o $@ $(LDLIBS)

# ---- dependencies --------------------------------------------------------------
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

bench-full: deps
	$(MAKE) $(B)/csgtrace
	bench/run.sh --full
	bench/accuracy.sh

# The primary pass in Mrays/s per core: packet and scalar kernels against the
# C worker's primary rays, N = 10 .. 10^4 spheres (bench/results/primary_pass).
bench-primary: deps
	$(MAKE) $(B)/csgtrace $(B)/bench/primary_pass
	bench/primary_pass.sh

# Speed versus accuracy (issue 6): every knob against a reference render.
bench-accuracy: deps
	$(MAKE) $(B)/csgtrace
	bench/accuracy.sh

# New golden images for tests/test_golden.c (look at them before committing).
golden: $(B)/csgtrace
	@for s in scenes/*.pov; do n=$$(basename $$s .pov); \
	  $(B)/csgtrace render $$s -o tests/golden/$$n.png --width 160 --height 120 || exit 1; done

clean:
	rm -rf build

-include $(shell find build -name '*.d' 2>/dev/null)
