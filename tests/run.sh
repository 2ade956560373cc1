#!/usr/bin/env bash
# tests/run.sh — every test of csgtrace, as `make test` runs it (after the
# optimised and the ASan+UBSan builds).  Each suite prints its own results;
# this script adds them up and ends with the line "N passed, N failed".
#
#   tests/run.sh            all suites
#   tests/run.sh unit       only the cmocka unit tests (both builds)
set -u
cd "$(dirname "$0")/.."
ROOT=$(pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export OMPI_MCA_rmaps_base_oversubscribe=1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
# Our program cache off unless asked for (e2e_hetero tests it in its own
# folder): storing a program makes PoCL compile every kernel's generic
# work-group function for the binary (CL_PROGRAM_BINARIES), which doubles
# a cold build (average.pov: 2.3 -> 4.7 s), and a clean clone builds some
# twenty programs cold; PoCL's own cache still keeps each one once built.
export CSGTRACE_CL_CACHE=${CSGTRACE_CL_CACHE:-off}
# intercept_tls_get_addr=0: LeakSanitizer's scan of the dynamic TLS that
# OpenImageIO's libraries allocate (test_image loads the module) read a
# bogus block and crashed its tracer ("Tracer caught signal 11", 3 runs in
# 25 under load); our code keeps no heap pointer in dynamic TLS.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:allocator_may_return_null=1:intercept_tls_get_addr=0}
export LSAN_OPTIONS="suppressions=$ROOT/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p "$POCL_CACHE_DIR" build/test-out

passed=0
failed=0
failed_suites=()
timings=() # "SECONDS SUITE", printed slowest first at the end

# timed NAME COMMAND...: runs it, noting its seconds under NAME.
timed() {
    local name=$1 t0=$SECONDS
    shift
    "$@"
    timings+=("$((SECONDS - t0)) $name")
}

# A cmocka binary's results, from its log and exit status: counted.
count_cmocka() {
    local bin=$1 log=$2 rc=$3 p f
    cat "$log"
    p=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' "$log" | tail -1)
    f=$(sed -n 's/^\[  FAILED  \] \([0-9]*\) test.*/\1/p' "$log" | tail -1)
    p=${p:-0}
    f=${f:-0}
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        f=1 # crashed or a sanitizer stopped it
    fi
    passed=$((passed + p))
    failed=$((failed + f))
    [ "$f" -gt 0 ] && failed_suites+=("$bin")
}

# run_cmocka_lanes DIR BIN...: the cmocka binaries in two lanes at once
# (each binary runs in-process, deterministic, asserting no time: two of
# them at a time on the two cores halves the wait; most of it is PoCL's
# compiles and the sanitised builds), each into DIR/K.log, .rc, .secs;
# then counted in the given order, so the output reads as one after the
# other.
run_cmocka_lanes() {
    local dir=$1 k
    shift
    local bins=("$@")
    lane() { # lane FIRST: binaries FIRST, FIRST + 2, ...
        local i t0
        for ((i = $1; i < ${#bins[@]}; i += 2)); do
            t0=$SECONDS
            "${bins[$i]}" >"$dir/$i.log" 2>&1
            echo $? >"$dir/$i.rc"
            echo $((SECONDS - t0)) >"$dir/$i.secs"
        done
    }
    lane 0 &
    lane 1
    wait
    for ((k = 0; k < ${#bins[@]}; k++)); do
        count_cmocka "${bins[$k]}" "$dir/$k.log" "$(cat "$dir/$k.rc")"
        timings+=("$(cat "$dir/$k.secs") ${bins[$k]}")
    done
}

# A script suite: it ends with "N passed, N failed".
run_script() {
    local script=$1 log
    shift
    log=$(mktemp)
    echo "=== $script $*"
    bash "$script" "$@" 2>&1 | tee "$log"
    local rc=${PIPESTATUS[0]}
    local line p f
    if [ "$rc" -eq 77 ]; then
        echo "$script: SKIPPED (a tool it needs is missing)"
        failed=$((failed + 1)) # make test promises every suite: a skip is a failure here
        failed_suites+=("$script (skipped)")
        rm -f "$log"
        return
    fi
    line=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$log" | tail -1)
    p=$(echo "$line" | sed -n 's/^\([0-9]*\) passed.*/\1/p')
    f=$(echo "$line" | sed -n 's/.* \([0-9]*\) failed.*/\1/p')
    p=${p:-0}
    f=${f:-0}
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        f=1
    fi
    passed=$((passed + p))
    failed=$((failed + f))
    [ "$f" -gt 0 ] && failed_suites+=("$script")
    rm -f "$log"
}

# A python unittest file: count its tests from "Ran N tests" and the
# failures/errors of its last line.
run_unittest() {
    local file=$1 log
    log=$(mktemp)
    echo "=== $file"
    python3 "$file" -v >"$log" 2>&1
    local rc=$?
    cat "$log"
    local n f
    n=$(sed -n 's/^Ran \([0-9]*\) test.*/\1/p' "$log" | tail -1)
    n=${n:-0}
    f=$(grep -c -E ' \.\.\. (FAIL|ERROR)$' "$log")
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        f=1
    fi
    passed=$((passed + n - f))
    failed=$((failed + f))
    [ "$f" -gt 0 ] && failed_suites+=("$file")
    rm -f "$log"
}

what=${1:-all}
cmocka_bins=()
for bin in build/tests/test_* build/asan/tests/test_*; do
    [ -x "$bin" ] && cmocka_bins+=("$bin")
done
cmocka_dir=$(mktemp -d)
run_cmocka_lanes "$cmocka_dir" "${cmocka_bins[@]}"
rm -rf "$cmocka_dir"
if [ "$what" = all ]; then
    for script in tests/e2e_*.sh; do
        [ -f "$script" ] && timed "$script" run_script "$script"
    done
    # geometry agreement with POV-Ray 3.7 on every example scene
    timed crosscheck_povray run_script tests/crosscheck_povray.sh
    # scenes of one feature each (tests/povray/: boxes of zero thickness)
    run_script tests/crosscheck_povray.sh tests/povray/*.pov
    # the NFF reader's scenes through `export` (99 %: the issue's bar)
    MIN_AGREEMENT=99 timed crosscheck_nff run_script tests/crosscheck_povray.sh tests/nff/*.nff
    # the camera statement in every order of its modifiers, read by POV-Ray
    timed crosscheck_camera run_script tests/crosscheck_camera.sh
    # the benchmark bookkeeping (medians, advantage, CSV columns)
    run_unittest bench/test_collect.py
    # the SPD report's confidence intervals and spd.sh --pairs
    run_unittest bench/test_spd_report.py
    # the SPD's tetra at sizes beyond the shipped files (bench/spd_big.sh)
    run_unittest bench/test_spd_subdivide.py
fi

echo
echo "the slowest suites (seconds):"
printf '%s\n' "${timings[@]}" | sort -rn | head -12 | sed 's/^/  /'
if [ ${#failed_suites[@]} -gt 0 ]; then
    echo "failing suites: ${failed_suites[*]}"
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
