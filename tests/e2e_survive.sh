#!/usr/bin/env bash
# e2e_survive.sh — a dead rank under `mpirun --enable-recovery`
# (comm/mpi_link.c: the watchdog sockets; host/master.c: lost workers):
#   - a worker SIGKILLed mid-render (homo and hetero, 3 and 4 ranks): exit
#     0, the serial image bit for bit, stats workers_lost = 1 and
#     items_reassigned >= 1, one line on stderr naming the worker; also
#     inside a batch (--batch 4: several items a message);
#   - a worker under a relay (--relays) SIGKILLed: its relay's whole group
#     is lost, the others finish, exit 0, the same image;
#   - every worker SIGKILLed: the master renders the rest itself, exit 0,
#     the same image, workers_lost = ranks - 1;
#   - a worker dead before its handshake; one dead during the scene
#     broadcast (the master sends the scene to each worker itself under
#     --enable-recovery: link_bcast); a worker killed over TCP; one
#     killed while its large result is on the way (TCP, shared memory);
#   - a worker that hangs (alive, silent): written off after its time
#     limit (HANG_REPEAT=N: N times; each takes over 10 s), same checks;
#   - a worker stopped (SIGSTOP): written off after a backstop of 2 s
#     (CSGTRACE_TEST_HANG_S), SIGKILLed by the master, mpirun returns;
#   - the master SIGKILLed: the workers exit by themselves, mpirun exits
#     non-zero, no image;
#   - compare (several renders in one job): a worker dead in the first
#     render, the others complete without it;
#   - a failed render (bad scene) under --enable-recovery: mpirun exits
#     non-zero (it would report 0: the master makes it fail);
# and after every run: no process of the run left, no shared-memory
# segment or session folder left (Open MPI's go to a private folder).
# The kills come from the test hook CSGTRACE_TEST_KILL_RANK /
# CSGTRACE_TEST_KILL_AFTER (comm/protocol.h: proto_test_kill).  A worker
# dies on its second item: the master gives every worker two at once, so
# even a worker starved of CPU on a loaded machine reaches it.
# REPEAT=N runs every case N times (default 1).
# Usage: tests/e2e_survive.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"
BIN=$HOOKED_BIN # (CSGTRACE_TEST_* hooks)

mpi_sandbox
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(pwd)/build/pocl-cache}
mkdir -p "$POCL_CACHE_DIR"
unset CSGTRACE_TEST_FAIL_WORKER CSGTRACE_TEST_KILL_RANK CSGTRACE_TEST_KILL_AFTER CSGTRACE_TEST_KILL_AT \
    CSGTRACE_TEST_HANG CSGTRACE_TEST_HANG_S
MPIRUN=(mpirun --enable-recovery --bind-to none --oversubscribe)
SCENE=scenes/csg_ops.pov
SZ=(--width 96 --height 64 --tile 8)
REPEAT=${REPEAT:-1}

if [ ! -x "$BIN" ]; then
    ko "$BIN is not built"
    e2e_finish
    exit 1
fi

# leftovers NAME: processes of run NAME, and Open MPI's files, still there
# (a process may take a moment to be reaped: up to 10 s).
leftovers() {
    local i
    for i in $(seq 50); do
        pgrep -f "$T/$1\." >/dev/null || break
        sleep 0.2
    done
    pgrep -f "$T/$1\." >/dev/null && echo "processes"
    [ -z "$(ls -A "$T/shm")" ] || echo "shm: $(ls "$T/shm" | head -3)"
    [ -z "$(find "$T/sess" -mindepth 1 -maxdepth 2)" ] || echo "session folders"
}

# run NAME NP ARGS...: mpirun with recovery; rc in $rc, stderr in NAME.err.
run() {
    local name=$1 np=$2
    shift 2
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} timeout -s KILL "${MPIRUN_S:-120}" \
        "${MPIRUN[@]}" -np "$np" "$BIN" render \
        "$SCENE" "${SZ[@]}" -o "$T/$name.exr" --stats "$T/$name.json" "$@" \
        >"$T/$name.out" 2>"$T/$name.err"
    rc=$?
}

# survived NAME LOST [MIN]: exit 0, the serial image, LOST workers lost
# and at least MIN items reassigned (default 1), one line per lost worker
# ($LOST_LINES lines when set: a relay's line covers its group), nothing
# left behind; else why not.
survived() {
    local name=$1 lost=$2 min=${3:-1} left
    left=$(leftovers "$name")
    if [ "$rc" != 0 ]; then
        echo "exit $rc: $(grep -v PMIX "$T/$name.err" | head -2)"
    elif ! same "$T/${REF:-ref}.exr" "$T/$name.exr"; then
        echo "pixels differ from serial"
    elif ! json "$T/$name.json" "j['workers_lost'] == $lost and j['items_reassigned'] >= $min"; then
        echo "stats: $(grep -E 'workers_lost|items_reassigned' "$T/$name.json" | tr -d '\n ')"
    elif [ "$(grep -c ' lost (' "$T/$name.err")" != "${LOST_LINES:-$lost}" ]; then
        echo "stderr: $(grep -c ' lost (' "$T/$name.err") lines of a lost worker"
    elif [ -n "$left" ]; then
        echo "left behind: $left"
    fi
}

# case_check DESCRIPTION FAILURES: one line for the N repetitions.
case_check() {
    if [ -z "$2" ]; then ok "$1 ($REPEAT/$REPEAT)"; else ko "$1:$2"; fi
}

if ! "$BIN" render "$SCENE" "${SZ[@]}" --mode serial -o "$T/ref.exr" >/dev/null 2>&1; then
    ko "serial reference render"
    e2e_finish
    exit 1
fi

modes=(homo)
if ! command -v clinfo >/dev/null 2>&1 || [ "$(clinfo -l 2>/dev/null | grep -c Platform)" != 0 ]; then
    modes+=(hetero)
fi

for mode in "${modes[@]}"; do
    for np in 3 4; do
        fails=""
        for i in $(seq "$REPEAT"); do
            name=kill-$mode-$np-$i
            CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=1 run "$name" "$np" --mode "$mode"
            why=$(survived "$name" 1)
            [ -n "$why" ] && fails="$fails [$i: $why]"
        done
        case_check "worker 2 SIGKILLed mid-render ($mode, $np ranks): exit 0, serial image, workers_lost 1, nothing left" "$fails"
    done
    np=3
    [ "$mode" = hetero ] && np=4
    fails=""
    for i in $(seq "$REPEAT"); do
        name=all-$mode-$i
        CSGTRACE_TEST_KILL_RANK=workers CSGTRACE_TEST_KILL_AFTER=1 run "$name" "$np" --mode "$mode"
        why=$(survived "$name" $((np - 1)))
        if [ -z "$why" ] && ! grep -q 'every worker was lost' "$T/$name.err"; then
            why="no line saying the master finishes alone"
        fi
        [ -n "$why" ] && fails="$fails [$i: $why]"
    done
    case_check "every worker SIGKILLed ($mode, $np ranks): the master finishes, exit 0, serial image" "$fails"
done

# Relays (--relays 2, 7 ranks: relay 1 deals to workers 3 and 5, relay 2
# to 4 and 6): worker 4 killed on its second item; rank 0 loses relay 2
# with its whole group (one line), their items go to relay 1's group, and
# relay 2 and worker 6, alive, exit when rank 0 lets them go.
for mode in "${modes[@]}"; do
    fails=""
    for i in $(seq "$REPEAT"); do
        name=relay-$mode-$i
        CSGTRACE_TEST_KILL_RANK=4 CSGTRACE_TEST_KILL_AFTER=1 run "$name" 7 --mode "$mode" --relays 2
        why=$(LOST_LINES=1 survived "$name" 3)
        if [ -z "$why" ] && ! grep -q 'relay 2 and its 2 workers lost' "$T/$name.err"; then
            why="no line naming relay 2 and its group: $(grep -v PMIX "$T/$name.err" | head -2)"
        fi
        [ -n "$why" ] && fails="$fails [$i: $why]"
    done
    case_check "worker 4 under relay 2 SIGKILLed ($mode, 7 ranks, --relays 2): its group lost (workers_lost 3), exit 0, serial image, nothing left" "$fails"
done

# Batches (--batch 4): worker 2 killed on the second item of its second
# batch; every item of the batches it held goes to the others.
for mode in "${modes[@]}"; do
    fails=""
    for i in $(seq "$REPEAT"); do
        name=batch-$mode-$i
        CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=5 run "$name" 3 --mode "$mode" --batch 4
        why=$(survived "$name" 1 2)
        if [ -z "$why" ] && ! json "$T/$name.json" "j['batch'] == 4 and j['tile_messages'] < j['items_sent']"; then
            why="not batched: $(grep -E '"(batch|tile_messages|items_sent)"' "$T/$name.json" | tr -d '\n ')"
        fi
        [ -n "$why" ] && fails="$fails [$i: $why]"
    done
    case_check "worker 2 SIGKILLed inside a batch ($mode, 3 ranks, --batch 4): exit 0, serial image, its items reassigned" "$fails"
done

# Pages served by their homes (--scene-memory, --page-home spread, 3
# workers): worker 2, the home of a third of the pages, killed on its
# second item; the others ask rank 0 for its pages instead (after
# LINK_PAGE_HOME_WAIT_NS, or at once when MPI reports the failure), and
# the image is the serial one.
PSCENE=$T/paged.pov
"$BIN" gen spheres --count 1000 --occupancy 0.6 --seed 11 --width 64 --height 48 -o "$PSCENE" >/dev/null &&
    "$BIN" render "$PSCENE" --width 64 --height 48 --tile 8 -o "$T/paged-ref.exr" --scene-memory 1 \
        --stats "$T/paged-probe.json" >/dev/null 2>&1 || ko "paged scene and its serial render"
PMB=$(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); r=j['scene_memory']['resident_bytes']; print((r + 0.6 * (j['blob_bytes'] - r)) / 1e6)" "$T/paged-probe.json")
for mode in "${modes[@]}"; do
    fails=""
    for i in $(seq "$REPEAT"); do
        name=home-$mode-$i
        args=(--mode "$mode")
        [ "$mode" = hetero ] && args+=(--pass always --fill off)
        saved_scene=$SCENE saved_sz=("${SZ[@]}")
        SCENE=$PSCENE SZ=(--width 64 --height 48 --tile 8)
        CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=1 \
            run "$name" 4 "${args[@]}" --scene-memory "$PMB" --page-home spread
        SCENE=$saved_scene SZ=("${saved_sz[@]}")
        why=$(REF=paged-ref survived "$name" 1)
        if [ -z "$why" ] && ! json "$T/$name.json" "j['scene_memory']['homes'] == 3 and j['paging']['rerouted'] > 0"; then
            why="the pages were not spread, or no ask went to rank 0 instead: $(grep -o '"rerouted": [0-9]*' "$T/$name.json" | head -1)"
        fi
        [ -n "$why" ] && fails="$fails [$i: $why]"
    done
    case_check "the home of a third of the pages SIGKILLed ($mode, 4 ranks, --page-home spread): exit 0, serial image, its pages from rank 0" "$fails"
done

# Other moments and transports: a worker dead before its handshake; a
# worker killed over TCP (no shared memory).
fails=""
for i in $(seq "$REPEAT"); do
    name=early-$i
    CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AT=ready CSGTRACE_TEST_KILL_AFTER=0 run "$name" 4 --mode homo
    why=$(survived "$name" 1 0)
    [ -n "$why" ] && fails="$fails [$i: $why]"
    name=scene-$i # (between the setup and the scene: the master is sending it)
    CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AT=scene CSGTRACE_TEST_KILL_AFTER=0 \
        run "$name" 4 --mode homo
    why=$(survived "$name" 1 0)
    [ -n "$why" ] && fails="$fails [$i scene: $why]"
    name=tcp-$i
    CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=1 OMPI_MCA_btl=tcp,self \
        run "$name" 3 --mode homo
    why=$(survived "$name" 1)
    [ -n "$why" ] && fails="$fails [$i tcp: $why]"
done
case_check "worker 2 dead before its handshake, and during the scene broadcast (homo, 4 ranks), and killed over TCP (homo, 3 ranks): exit 0, serial image, nothing left" "$fails"

# Killed while its result (110 KB: 96 x 96 pixels, over every eager
# limit) is on its way, over TCP and over shared memory.
SZ=(--width 192 --height 192 --tile 96)
if "$BIN" render "$SCENE" "${SZ[@]}" --mode serial -o "$T/big.exr" >/dev/null 2>&1; then
    fails=""
    for i in $(seq "$REPEAT"); do
        for btl in tcp vader; do
            name=send-$btl-$i
            CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AT=send CSGTRACE_TEST_KILL_AFTER=0 \
                OMPI_MCA_btl=$btl,self run "$name" 3 --mode homo
            why=$(REF=big survived "$name" 1)
            [ -n "$why" ] && fails="$fails [$i $btl: $why]"
        done
    done
    case_check "worker 2 killed while sending a 110 KB result (homo, 3 ranks, TCP and shared memory): exit 0, serial image" "$fails"
else
    ko "serial render at 192x192"
fi
SZ=(--width 96 --height 64 --tile 8)

# A hung worker (it waits for ever on its second item, its process alive):
# written off after the backstop (max(10 x the mean item, 10 s)).
fails=""
for i in $(seq "${HANG_REPEAT:-1}"); do
    name=hang-$i
    CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=1 CSGTRACE_TEST_HANG=1 run "$name" 3 --mode homo
    why=$(survived "$name" 1)
    if [ -z "$why" ] && ! grep -q 'worker 2 lost (no answer for' "$T/$name.err"; then
        why="not lost for its silence: $(grep -v PMIX "$T/$name.err" | head -1)"
    fi
    [ -n "$why" ] && fails="$fails [$i: $why]"
done
REPEAT=${HANG_REPEAT:-1} case_check "a hung worker (homo, 3 ranks): written off after its time limit, exit 0, serial image" "$fails"

# A stopped worker (SIGSTOP: it cannot even exit when its watchdog socket
# closes) is written off after the backstop (CSGTRACE_TEST_HANG_S=2), then
# SIGKILLed by the master (a process of this host); mpirun once waited for
# it for ever.  (mpirun's own limit here: 40 s.)
fails=""
for i in $(seq "$REPEAT"); do
    name=stopped-$i
    CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=1 CSGTRACE_TEST_HANG=stop \
        CSGTRACE_TEST_HANG_S=2 MPIRUN_S=40 run "$name" 3 --mode homo
    why=$(survived "$name" 1)
    [ -n "$why" ] && fails="$fails [$i: $why]"
    for p in $(pgrep -f "$T/$name\."); do kill -KILL "$p"; done # (left stopped: the old way)
done
case_check "a stopped worker (SIGSTOP, homo, 3 ranks): written off, killed, exit 0, serial image, nothing left" "$fails"

fails=""
for i in $(seq "$REPEAT"); do
    name=master-$i
    CSGTRACE_TEST_KILL_RANK=0 CSGTRACE_TEST_KILL_AFTER=3 run "$name" 4 --mode homo
    left=$(leftovers "$name")
    if [ "$rc" = 0 ] || [ "$rc" = 137 ]; then
        fails="$fails [$i: mpirun exit $rc]"
    elif [ -e "$T/$name.exr" ]; then
        fails="$fails [$i: an image was written]"
    elif ! grep -q 'the master is gone' "$T/$name.err"; then
        fails="$fails [$i: no worker said the master is gone]"
    elif [ -n "$left" ]; then
        fails="$fails [$i: left behind: $left]"
    fi
done
case_check "the master SIGKILLed (homo, 4 ranks): the workers exit, mpirun fails, nothing left" "$fails"

printf 'sphere { <0, 0, 0>, 1 @@@ }\n' >"$T/bad.pov"
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} timeout -s KILL 120 "${MPIRUN[@]}" -np 3 "$BIN" render "$T/bad.pov" \
    --mode homo -o "$T/bad.exr" >"$T/bad.out" 2>"$T/bad.err"
rc=$?
if [ "$rc" != 0 ] && [ "$rc" != 137 ] && [ "$(grep -c ': error: ' "$T/bad.err")" = 1 ]; then
    ok "a bad scene under --enable-recovery: mpirun exits non-zero ($rc), one message"
else
    ko "a bad scene under --enable-recovery: mpirun exit $rc, $(grep -c ': error: ' "$T/bad.err") messages"
fi

# compare: several renders in one job (homo and hetero, interleaved);
# worker 2 dies in the first: the later ones go on without it
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AFTER=2 \
    timeout -s KILL 120 "${MPIRUN[@]}" -np 4 "$BIN" compare "$SCENE" "${SZ[@]}" --repeat 1 \
    >"$T/compare.out" 2>"$T/compare.err"
rc=$?
left=$(leftovers compare)
if [ "$rc" = 0 ] && grep -q "identical, bit for bit" "$T/compare.out" &&
    [ "$(grep -c "worker 2 lost" "$T/compare.err")" = 1 ] && [ -z "$left" ]; then
    ok "compare, worker 2 SIGKILLed in its first render (4 ranks): every render completes, identical images, the loss reported once"
else
    ko "compare with a dead worker: exit $rc, left: $left, stderr: $(grep -v PMIX "$T/compare.err" | head -c 300)"
fi

run plain-3 3 --mode homo
if [ "$rc" = 0 ] && same "$T/ref.exr" "$T/plain-3.exr" &&
    json "$T/plain-3.json" "j['workers_lost'] == 0 and j['items_reassigned'] == 0"; then
    ok "no rank dies under --enable-recovery: exit 0, serial image, workers_lost 0"
else
    ko "no rank dies under --enable-recovery: exit $rc"
fi

e2e_finish
