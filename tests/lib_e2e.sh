# lib_e2e.sh — what the end-to-end scripts share (sourced, not run): the
# binary under test, a scratch folder removed on exit, the pass/fail
# counters and the checks on images and JSON.  Each script ends with
# `e2e_finish`, which prints "N passed, N failed" (tests/run.sh reads it).
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
BIN=${CSGTRACE_BIN:-build/csgtrace}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
pass=0
fail=0
ok() { echo "ok   - $1"; pass=$((pass + 1)); }
ko() { echo "FAIL - $1"; fail=$((fail + 1)); }

# same A B: the two images have exactly the same pixels.
same() { idiff -fail 0 -warn 0 "$1" "$2" >/dev/null 2>&1; }

# json FILE EXPR: a python expression over the parsed JSON `j` is true.
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1"; }

e2e_finish() {
    echo "$pass passed, $fail failed"
    [ "$fail" -eq 0 ]
}
