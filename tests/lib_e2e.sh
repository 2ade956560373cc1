# lib_e2e.sh — what the end-to-end scripts share (sourced, not run): the
# binary under test, a scratch folder removed on exit, the pass/fail
# counters and the checks on images and JSON.  Each script ends with
# `e2e_finish`, which prints "N passed, N failed" (tests/run.sh reads it).
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
BIN=${CSGTRACE_BIN:-build/csgtrace}
# The same program with the test hooks (comm/test_hooks.h: CSGTRACE_TEST_*),
# for the scripts that use them; build/csgtrace reads none.
HOOKED_BIN=${CSGTRACE_TEST_BIN:-build/csgtrace-test}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
pass=0
fail=0
ok() { echo "ok   - $1"; pass=$((pass + 1)); }
ko() { echo "FAIL - $1"; fail=$((fail + 1)); }

# same A B: the two images have exactly the same pixels.  Two PFMs (float
# files csgtrace writes itself, header and floats: the suites' images, no
# OpenImageIO to load) are compared byte for byte, so bit for bit.
same() {
    if [[ $1 == *.pfm && $2 == *.pfm ]]; then
        [ -f "$1" ] && cmp -s "$1" "$2"
    else # (the same bytes: the same pixels, without starting idiff)
        [ -f "$1" ] && cmp -s "$1" "$2" || idiff -fail 0 -warn 0 "$1" "$2" >/dev/null 2>&1
    fi
}

# json FILE EXPR: a python expression over the parsed JSON `j` is true.
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1"; }

# mpi_sandbox: mpirun allowed as root, the ob1 layer (half the start-up),
# and Open MPI's shared-memory segments and session folders under $T, so
# a test can check that none is left behind.
mpi_sandbox() {
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
    export OMPI_MCA_btl_vader_backing_directory=$T/shm OMPI_MCA_orte_tmpdir_base=$T/sess
    mkdir -p "$T/shm" "$T/sess"
}

# slow_scene FILE: 300 random spheres, seconds to render at a few
# megapixels: long enough to be stopped half-way.
slow_scene() {
    "$BIN" gen spheres --count 300 --occupancy 0.6 --seed 2 --width 64 --height 64 \
        -o "$1" >/dev/null || ko "gen $1"
}

e2e_finish() {
    echo "$pass passed, $fail failed"
    [ "$fail" -eq 0 ]
}
