#!/usr/bin/env bash
# e2e_asan.sh — the whole program under AddressSanitizer + UBSan, end to
# end: every example scene and the NFF test scenes rendered by the
# sanitised binary (build/asan/csgtrace) in serial, homo and hetero (with
# and without the fill, with the cost order), and on one scene with relays,
# the tail schedule, double precision and an image large enough for the
# master's page-faulting thread.  Each image must equal the
# optimised binary's serial image bit for bit, each run must exit 0, and no
# rank may print a sanitizer report (leaks included: tests/lsan.supp
# suppresses only the libraries we do not own).
#
# use_sigaltstack=0: PoCL's LLVM gives each thread it runs on a larger
# alternate signal stack of its own (malloc'd); at that thread's exit ASan
# would unmap it as if it were its own and stop ("failed to deallocate").
# Our code installs no alternate stack, so nothing of ours is hidden.
set -u
source "$(dirname "$0")/lib_e2e.sh"
mpi_sandbox
export OMPI_MCA_rmaps_base_oversubscribe=1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(pwd)/build/pocl-cache}
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:allocator_may_return_null=1:use_sigaltstack=0:intercept_tls_get_addr=0 # (run.sh says why)
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0:exitcode=0"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ABIN=${CSGTRACE_ASAN_BIN:-build/asan/csgtrace}
MPIRUN=(mpirun --bind-to none)
if [ ! -x "$ABIN" ]; then
    ko "no sanitised binary at $ABIN (make asan)"
    e2e_finish
    exit
fi

# our_leaks FILE: the leak reports in FILE whose allocation stack passes
# through our sources.  Open MPI unloads its components at MPI_Finalize,
# so the leaks it leaves there are reported from "<unknown module>" and no
# suppression can name them; our code is never unloaded, so its frames are
# always named.
our_leaks() {
    awk '/^(Direct|Indirect) leak of/ { block = $0; keep = 0; inside = 1; next }
         inside && /^$/ { if (keep) print block; inside = 0; next }
         inside { block = block "\n" $0
                  if ($0 ~ / (host|workers|csg|scenes|simd_kernels)\/[A-Za-z0-9_\/]+\.[ch]:/) keep = 1 }
         END { if (inside && keep) print block }' "$1"
}

# clean NAME: the run NAME exited 0 and printed no sanitizer report but
# leaks outside our code (LSAN_OPTIONS exitcode=0: leak reports leave the
# exit code alone; our_leaks reads them).
clean() {
    [ "$(cat "$T/$1.rc")" = 0 ] &&
        ! grep -qE 'ERROR: AddressSanitizer|runtime error:|Sanitizer CHECK' "$T/$1.err" &&
        [ -z "$(our_leaks "$T/$1.err")" ]
}

# sanitised NAME RANKS MODE SCENE EXTRA...: one render by the sanitised
# binary (RANKS 0: no mpirun) -> $T/NAME.png, .err, .rc
sanitised() {
    local name=$1 ranks=$2 mode=$3 scene=$4
    shift 4
    local run=("$ABIN")
    [ "$ranks" -gt 0 ] && run=("${MPIRUN[@]}" -np "$ranks" "$ABIN")
    timeout 300 "${run[@]}" render "$scene" -o "$T/$name.png" --mode "$mode" "$@" \
        >/dev/null 2>"$T/$name.err"
    echo $? >"$T/$name.rc"
}

# check NAME REF WHAT: the run was clean and its image is REF's.
check() {
    if clean "$1" && same "$T/$2.png" "$T/$1.png"; then
        ok "asan: $3"
    else
        ko "asan: $3 (exit $(cat "$T/$1.rc"); $(grep -m1 -E 'ERROR|error|runtime' "$T/$1.err"))"
    fi
}

# (at 160x120: every code path of a scene runs at any size, and each
# sanitised render costs several optimised ones)
SMALL=(--width 160 --height 120)
for scene in scenes/*.pov tests/nff/*.nff; do
    n=$(basename "$scene" | tr . _)
    if ! "$BIN" render "$scene" "${SMALL[@]}" -o "$T/$n.png" --mode serial >/dev/null 2>&1; then
        ko "optimised serial render of $scene"
        continue
    fi
    sanitised "${n}_s" 0 serial "$scene" "${SMALL[@]}"
    check "${n}_s" "$n" "$scene serial"
    sanitised "${n}_h" 3 homo "$scene" "${SMALL[@]}"
    check "${n}_h" "$n" "$scene homo, 2 workers"
    CSGTRACE_TEST_PASS_PAYS_MS=1 sanitised "${n}_x" 3 hetero "$scene" "${SMALL[@]}"
    check "${n}_x" "$n" "$scene hetero (the fill; the device opened on rank 0's guess)"
    sanitised "${n}_c" 3 hetero "$scene" "${SMALL[@]}" --fill off --schedule cost
    check "${n}_c" "$n" "$scene hetero --fill off --schedule cost"
done

scene=scenes/showcase.pov
"$BIN" render "$scene" -o "$T/showcase_full.png" --mode serial >/dev/null 2>&1
# (the pass's threshold out of reach: under ASan rank 0's guess of the frame
# is several times a plain build's, and crossed the real one once)
CSGTRACE_TEST_PASS_PAYS_MS=999999 sanitised relay 5 hetero "$scene" --relays 2 --schedule cost \
    --stats "$T/relay.json"
if python3 -c "import json,sys; sys.exit(json.load(open('$T/relay.json'))['cl_open'] != 'never')" \
    2>/dev/null; then
    check relay showcase_full "$scene hetero, 2 relays of 1 worker each (--pass auto: the fill alone)"
else
    ko "asan: the relay run was meant to leave the device closed (cl_open never)"
fi
# 12 MiB of image: the master's page-faulting thread runs (host/memory.h)
"$BIN" render scenes/primitives.pov -o "$T/big_ref.png" --mode serial --width 1024 --height 1024 \
    >/dev/null 2>&1
sanitised big 3 homo scenes/primitives.pov --width 1024 --height 1024
check big big_ref "scenes/primitives.pov homo at 1024x1024 (the image's pages faulted in by a thread)"
sanitised tail 4 homo "$scene" --schedule tail --tile 8
check tail showcase_full "$scene homo --schedule tail --tile 8, 3 workers"
"$BIN" render "$scene" -o "$T/showcase_d.png" --mode serial --precision double >/dev/null 2>&1
sanitised double 3 hetero "$scene" --precision double --fill off
check double showcase_d "$scene hetero in double precision"

# --scene-memory (workers/pager.h): the scene in pages of 16 KiB below a
# budget of its resident part and a few pages, the pages fetched from rank
# 0 (and, serially under mpirun, from rank 0's copy once it moved into the
# node's shared mapping)
"$BIN" gen spheres --count 1000 --occupancy 0.6 --seed 11 --width 64 --height 48 \
    --materials opaque,reflective,transparent -o "$T/paged.pov" >/dev/null 2>&1
"$BIN" render "$T/paged.pov" -o "$T/paged_ref.png" --width 64 --height 48 --tile 8 >/dev/null 2>&1
for mode in serial homo hetero; do
    sanitised "paged_$mode" 3 $mode "$T/paged.pov" --width 64 --height 48 --tile 8 \
        --scene-memory 0.44 --page-size 16 --pass always --fill off
    check "paged_$mode" paged_ref "--scene-memory 0.44 (a 0.58 MB scene, 0.37 MB resident), $mode under mpirun"
done
# ... the shadow rays' pages prefetched too (--page-prefetch shadows: the
# walks of workers/shade.c, prefetch_shadow_pages)
for mode in homo hetero; do
    sanitised "shadows_$mode" 3 $mode "$T/paged.pov" --width 64 --height 48 --tile 8 \
        --scene-memory 0.44 --page-size 16 --page-prefetch shadows --pass always --fill off
    check "shadows_$mode" paged_ref "--scene-memory 0.44 --page-prefetch shadows, $mode under mpirun"
done
# ... and the pages' homes (--page-home spread): 3 workers, each the home of
# a third of the pages, answering the others while it renders
for mode in homo hetero; do
    sanitised "homes_$mode" 4 $mode "$T/paged.pov" --width 64 --height 48 --tile 8 \
        --scene-memory 0.60 --page-size 16 --page-home spread --pass always --fill off
    check "homes_$mode" paged_ref "--scene-memory 0.60 --page-home spread, $mode, 3 workers"
done

# failing NAME ERRORS TEXT WHAT: the run NAME failed as it should (exit
# 1) with ERRORS error lines, one holding TEXT, no image, no sanitizer
# report of ours.
failing() {
    local rc lines
    rc=$(cat "$T/$1.rc")
    lines=$(grep -v -E 'Sanitizer|^ *#|^SUMMARY' "$T/$1.err" | grep -c 'error')
    if [ "$rc" = 1 ] && [ "$lines" = "$2" ] && grep -q "$3" "$T/$1.err" &&
        [ ! -e "$T/$1.png" ] && ! grep -qE 'ERROR: AddressSanitizer|runtime error:' "$T/$1.err" &&
        [ -z "$(our_leaks "$T/$1.err")" ]; then
        ok "asan: $4"
    else
        ko "asan: $4 (exit $rc, $lines error lines: $(grep -m2 -E 'error|ERROR' "$T/$1.err" | tr '\n' ' '))"
    fi
}

CSGTRACE_TEST_FAIL_WORKER=2 sanitised fail 3 homo "$scene" --tile 8
failing fail 1 'worker 2' "worker 2 fails (homo, 2 workers): one message, no image, no leak of ours"
CSGTRACE_TEST_FAIL_WORKER=3 sanitised relay-fail 5 hetero "$scene" --tile 8 --relays 2
failing relay-fail 1 'worker 3' "worker 3 fails under relay 1 (hetero, 2 relays): one message, no image, no leak of ours"
printf 'camera { location <0,0,-5> look_at <0,0,0> }\nsphere { <0,0,0>, }\n' >"$T/bad.pov"
sanitised bad 3 homo "$T/bad.pov"
if [ "$(cat "$T/bad.rc")" = 2 ] && grep -q "bad.pov:2:.*error" "$T/bad.err" && [ ! -e "$T/bad.png" ] &&
    ! grep -qE 'ERROR: AddressSanitizer|runtime error:' "$T/bad.err" && [ -z "$(our_leaks "$T/bad.err")" ]; then
    ok "asan: a scene error under mpirun: exit 2, file:line:col, no image, no leak of ours"
else
    ko "asan: a scene error under mpirun (exit $(cat "$T/bad.rc"): $(head -2 "$T/bad.err" | tr '\n' ' '))"
fi

e2e_finish
