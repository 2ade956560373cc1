#!/usr/bin/env bash
# e2e_mpi.sh — end-to-end checks of the render driver and the MPI
# master/worker (host/render.c, host/master.c, workers/worker.c) through
# build/csgtrace:
#   - serial == homo == hetero, bit for bit (PFM float pixels compared byte
#     for byte), over the example scenes, tile sizes 1, 7, 32
#     and larger than the image, K = 1, 2, 3, 5 ranks, sizes that are not
#     multiples of the tile, both precisions, the TCP transport;
#   - a scene error under mpirun: exit 2 and one message;
#   - a worker failure (CSGTRACE_TEST_FAIL_WORKER), a worker that breaks the
#     protocol (tests/rogue_worker.c) and an OpenCL failure: exit 1, one
#     message, no image;
#   - the stats JSON holds every field, and its counts add up; the phases
#     add up to wall_s within a millisecond;
#   - batches (--batch N: several items a TILE, one RESULT for them):
#     serial == homo == hetero with odd parts (tile 7: padding between
#     parts; both precisions), every schedule, and fewer TILE messages
#     than items; a rogue worker's batched answer with a part for the
#     wrong tile, or with too few parts, is refused;
#   - relays (--relays K): serial == homo == hetero with 1 to 3 relays,
#     every schedule, items computed by workers only, parts dealt several a
#     message, over TCP; too few ranks is exit 2; a failing or rogue worker
#     under a relay ends the render with one message naming it;
#   - every --schedule (raster, cost, static, tail, region), homo and hetero, on
#     1 to 5 ranks: the same image as serial, and a tile log that covers
#     every tile exactly once (whole or as pieces), agrees with the stats
#     and with the schedule (static: the k-th tile on worker k mod W, or
#     under relays on a worker of relay k mod K);
#   - one copy of the scene per node (comm/mpi_link.h: link_scene): homo
#     and under a relay every rank reads the master's copy in place (the
#     stats' scene_shared_ranks, which a worker counts only once it has
#     mapped that copy); nodes of 2 ranks pretended (homo, and hetero under
#     --enable-recovery): the other leaders' nodes read their leader's copy,
#     a rank alone on its node its own, and a leader killed before the
#     scene takes the rank waiting on it with it; with CSGTRACE_NODE_SCENE=off every
#     rank holds its own; the same image as serial every time.
# Prints one line per check and "N passed, N failed"; exits 1 on failure.
# Usage: tests/e2e_mpi.sh [path/to/csgtrace]   (default build/csgtrace)
set -u

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/csgtrace-test} # (with the test hooks: CSGTRACE_TEST_FAIL_WORKER)
TMP=$(mktemp -d "${TMPDIR:-/tmp}/csgtrace-mpi.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
mkdir -p "$POCL_CACHE_DIR"
# A job this suite makes fail on purpose (a rogue or failing worker) ends
# in MPI_Abort; mpirun then waits odls_base_sigkill_timeout (1 s) before it
# kills a rank that has not left (the rogue worker never does): 1-2 s a
# case, a third of the suite.  What the render does before it aborts (its
# one message, no image) is what is checked, and it is done by then.
export OMPI_MCA_odls_base_sigkill_timeout=0
unset CSGTRACE_TEST_FAIL_WORKER
MPIRUN=(mpirun --bind-to none --oversubscribe)
W=64 H=48

passed=0 failed=0
ok()   { passed=$((passed + 1)); echo "ok   - $*"; }
bad()  { failed=$((failed + 1)); echo "FAIL - $*"; }
skip() { echo "skip - $*"; }
check() { # check DESCRIPTION COMMAND...
    local d=$1; shift
    if "$@"; then ok "$d"; else bad "$d"; fi
}

if [ ! -x "$BIN" ]; then
    echo "FAIL - $BIN is not built"
    echo "0 passed, 1 failed"
    exit 1
fi

# render NAME NP ARGS...: renders into $TMP/NAME.pfm; NP 0: without mpirun;
# $MPIX: more mpirun options.
# Its stderr is kept in $TMP/NAME.err; returns csgtrace's (mpirun's) status.
render() {
    local name=$1 np=$2; shift 2
    if [ "$np" = 0 ]; then
        "$BIN" render "$@" -o "$TMP/$name.pfm" >"$TMP/$name.out" 2>"$TMP/$name.err"
    else
        # Open MPI's own allocations look leaked to LeakSanitizer (an ASan
        # build given as $1): leaks are checked by the serial runs only.
        # shellcheck disable=SC2086  # MPIX: extra mpirun options, split
        ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} \
        "${MPIRUN[@]}" ${MPIX:-} -np "$np" "$BIN" render "$@" -o "$TMP/$name.pfm" \
            >"$TMP/$name.out" 2>"$TMP/$name.err"
    fi
}

# same A B: the two images exist and their pixels are identical, bit for
# bit (a PFM's bytes are its header and its floats: csgtrace writes it
# itself, without loading OpenImageIO, the renders' main cost here).
same() {
    [ -f "$TMP/$1.pfm" ] && [ -f "$TMP/$2.pfm" ] && cmp -s "$TMP/$1.pfm" "$TMP/$2.pfm"
}

# render_same DESCRIPTION REF NAME NP ARGS...: renders NAME, compares with REF.
render_same() {
    local d=$1 ref=$2 name=$3 rc; shift 3
    render "$name" "$@"
    rc=$?
    if [ $rc != 0 ]; then
        bad "$d (exit $rc: $(grep -m1 ': error: ' "$TMP/$name.err"))"
    elif same "$ref" "$name"; then
        ok "$d"
    else
        bad "$d (pixels differ from $ref)"
    fi
}

# error_lines NAME: lines of our own messages (mpirun's banners excluded).
error_lines() { grep -c ': error: ' "$TMP/$1.err"; }

# ---- scenes --------------------------------------------------------------
scenes=()
for s in "$ROOT"/scenes/*.pov; do [ -f "$s" ] && scenes+=("$s"); done
if [ ${#scenes[@]} -eq 0 ]; then
    cat >"$TMP/fallback.pov" <<'EOF'
camera { location <0, 1, -4> look_at <0, 0, 0> }
light_source { <3, 5, -4> color rgb <1, 1, 1> }
background { color rgb <0.1, 0.2, 0.3> }
difference {
  sphere { <0, 0, 0>, 1 pigment { color rgb <1, 0.2, 0.2> } finish { reflection 0.3 } }
  box { <-0.5, -0.5, -2>, <0.5, 0.5, 0> pigment { color rgb <0.2, 1, 0.2> } }
}
plane { <0, 1, 0>, -1 pigment { color rgb <0.8, 0.8, 0.8> } }
EOF
    scenes=("$TMP/fallback.pov")
    skip "no scenes/*.pov: using a built-in scene"
fi
first=${scenes[0]}
SZ=(--width "$W" --height "$H")

have_cl=1
if command -v clinfo >/dev/null 2>&1 && [ "$(clinfo -l 2>/dev/null | grep -c Platform)" = 0 ]; then
    have_cl=0
    skip "no OpenCL platform (clinfo -l): hetero checks skipped"
fi

# ---- every scene: serial == homo == hetero ----------------------------------
for s in "${scenes[@]}"; do
    n=$(basename "$s" .pov)
    if ! render "$n-ref" 0 "$s" "${SZ[@]}" --mode serial; then
        bad "$n: serial render ($(grep -m1 ': error: ' "$TMP/$n-ref.err"))"
        continue
    fi
    ok "$n: serial render"
    render_same "$n: serial tile 7 == serial tile 32" "$n-ref" "$n-s7" 0 "$s" "${SZ[@]}" \
        --mode serial --tile 7
    render_same "$n: homo K=3 tile 7 == serial" "$n-ref" "$n-h3" 3 "$s" "${SZ[@]}" \
        --mode homo --tile 7
    if [ $have_cl = 1 ]; then
        render_same "$n: hetero K=3 tile 7 == serial" "$n-ref" "$n-x3" 3 "$s" "${SZ[@]}" \
            --mode hetero --tile 7
    fi
done

# ---- randomness: area_light jitter and crand draw from a hash of the pixel ----
# (workers/shade.c), so every mode, tile size and rank count gives the same
# bytes (the scene's kinds are those of scenes/shadows.pov: no new OpenCL
# program to build)
cat >"$TMP/random.pov" <<'EOF'
camera { location <0, 2, -5> look_at <0, 0.5, 0> }
light_source { <2, 5, -3> color rgb 1 area_light <2, 0, 0>, <0, 0, 2>, 4, 4 adaptive 1 jitter }
plane { y, 0 pigment { rgb 0.8 } finish { crand 0.2 } }
sphere { <0, 1, 0>, 1 pigment { rgb <0.9, 0.5, 0.3> } finish { crand 0.1 } }
box { <1.2, 0, -0.5>, <2, 0.8, 0.3> pigment { rgb <0.4, 0.6, 0.9> } rotate y * 20 }
cylinder { <-2, 0, 1>, <-2, 1.5, 1>, 0.3 pigment { rgb 0.6 } }
EOF
if render rnd-ref 0 "$TMP/random.pov" "${SZ[@]}" --mode serial --spp 2; then
    ok "jitter + crand: serial render"
    render_same "jitter + crand: serial tile 5 == serial" rnd-ref rnd-s5 0 "$TMP/random.pov" \
        "${SZ[@]}" --mode serial --spp 2 --tile 5
    render_same "jitter + crand: homo K=3 tile 7 == serial" rnd-ref rnd-h3 3 "$TMP/random.pov" \
        "${SZ[@]}" --mode homo --spp 2 --tile 7
    [ $have_cl = 1 ] && render_same "jitter + crand: hetero K=2 tile 9 == serial" rnd-ref rnd-x2 2 \
        "$TMP/random.pov" "${SZ[@]}" --mode hetero --spp 2 --tile 9
else
    bad "jitter + crand: serial render ($(grep -m1 ': error: ' "$TMP/rnd-ref.err"))"
fi

# ---- the first scene: tiles, ranks, odd sizes, precision, transport ------------
n=$(basename "$first" .pov)
R=$n-ref
render_same "homo K=2 tile 32 == serial" "$R" m-h2 2 "$first" "${SZ[@]}" --mode homo --tile 32
render_same "homo K=5 tile 1 == serial" "$R" m-h5 5 "$first" "${SZ[@]}" --mode homo --tile 1
render_same "homo K=3 tile 100 (> image) == serial" "$R" m-hbig 3 "$first" "${SZ[@]}" \
    --mode homo --tile 100
render_same "homo K=1 (serial path under mpirun) == serial" "$R" m-h1 1 "$first" "${SZ[@]}" \
    --mode homo
MPIX="--mca btl tcp,self" render_same "homo K=3 over TCP (--mca btl tcp,self) == serial" "$R" \
    m-tcp 3 "$first" "${SZ[@]}" --mode homo --tile 16

if render odd-ref 0 "$first" --width 61 --height 37 --mode serial --tile 32; then
    ok "61x37 serial render"
    render_same "61x37 homo K=3 tile 8 == serial" odd-ref odd-h3 3 "$first" \
        --width 61 --height 37 --mode homo --tile 8
    [ $have_cl = 1 ] && render_same "61x37 hetero K=2 tile 7 == serial" odd-ref odd-x2 2 \
        "$first" --width 61 --height 37 --mode hetero --tile 7
else
    bad "61x37 serial render"
fi

if render dbl-ref 0 "$first" "${SZ[@]}" --mode serial --precision double; then
    ok "double serial render"
    render_same "double homo K=3 tile 7 == serial" dbl-ref dbl-h3 3 "$first" "${SZ[@]}" \
        --mode homo --tile 7 --precision double
    [ $have_cl = 1 ] && render_same "double hetero K=3 tile 7 == serial" dbl-ref dbl-x3 3 \
        "$first" "${SZ[@]}" --mode hetero --tile 7 --precision double
else
    bad "double serial render"
fi

if [ $have_cl = 1 ]; then
    render_same "hetero without mpirun == serial" "$R" m-x0 0 "$first" "${SZ[@]}" --mode hetero
    render_same "hetero K=1 == serial" "$R" m-x1 1 "$first" "${SZ[@]}" --mode hetero --tile 5
    render_same "hetero K=5 tile 1 == serial" "$R" m-x5 5 "$first" "${SZ[@]}" --mode hetero --tile 1
    render_same "hetero K=2 tile 100 (> image) == serial" "$R" m-xbig 2 "$first" "${SZ[@]}" \
        --mode hetero --tile 100
fi

# ---- stats JSON ----------------------------------------------------------------
check_stats() { # check_stats FILE MODE RANKS
    python3 - "$@" <<'EOF'
import json, sys
path, mode, ranks = sys.argv[1], sys.argv[2], int(sys.argv[3])
s = json.load(open(path))
need = ["mode", "width", "height", "tile", "ranks", "wall_s", "primary_s", "secondary_s",
        "compile_s", "tiles_total", "tiles_sent", "tiles_degenerate", "occupancy", "rays",
        "bytes_sent", "precision", "workers"]
missing = [k for k in need if k not in s]
missing += ["rays." + k for k in ("primary", "shadow", "reflected", "refracted")
            if k not in s.get("rays", {})]
assert not missing, "missing: %s" % missing
assert s["mode"] == mode and s["ranks"] == ranks, (s["mode"], s["ranks"])
assert s["tiles_sent"] + s["tiles_degenerate"] == s["tiles_total"]
assert 0.0 <= s["occupancy"] <= 1.0
assert s["rays"]["primary"] == s["width"] * s["height"], s["rays"]
ws = s["workers"]
assert len(ws) == max(ranks - 1 - s["relays"], 1), len(ws)
assert s["relays"] == 0 or all(w["rank"] > s["relays"] for w in ws), ws
for w in ws:
    for k in ("rank", "tiles", "rays", "busy_s"):
        assert k in w, "worker field " + k
assert sum(w["tiles"] for w in ws) == s["tiles_sent"]
if ranks > 1:
    assert s["bytes_sent"] > 0
phases = ["setup_s", "cl_setup_s", "compile_s", "primary_s", "pipelined_s", "secondary_s",
          "write_s"]
assert abs(sum(s[k] for k in phases) - s["wall_s"]) < 1e-3, [s[k] for k in phases]
assert all(s[k] >= -1e-9 for k in phases), [s[k] for k in phases]
assert 0.0 <= s["busy_fraction"] <= 1.0 + 1e-6 and s["tail_s"] >= 0
# the master's time taking results in: some when workers sent any, and
# within the tile phase it is part of
assert 0.0 <= s["master_results_s"] <= s["tile_phase_s"] + 1e-6, s["master_results_s"]
assert (s["master_results_s"] > 0) == (ranks > 1 and s["tiles_sent"] > 0), s["master_results_s"]
EOF
}

# check_tile_log LOG STATS SCHEDULE: the log covers every tile once (whole
# or as pieces that partition it), agrees with the stats and the schedule.
check_tile_log() {
    python3 - "$@" <<'EOF'
import json, sys
log, stats, schedule = sys.argv[1], sys.argv[2], sys.argv[3]
s = json.load(open(stats))
items = [json.loads(line) for line in open(log)]
W, H, T = s["width"], s["height"], s["tile"]
cols = (W + T - 1) // T
assert s["schedule"] == schedule, s["schedule"]
area, skipped, sent = {}, 0, []
for it in items:
    t = it["tile"]
    tx, ty = t % cols * T, t // cols * T
    tw, th = min(T, W - tx), min(T, H - ty)
    assert tx <= it["x"] and ty <= it["y"], it
    assert it["x"] + it["width"] <= tx + tw and it["y"] + it["height"] <= ty + th, it
    area[t] = area.get(t, 0) + it["width"] * it["height"]
    if it["skipped"]:
        skipped += 1
        assert it["order"] is None and it["piece"] == 0
    else:
        sent.append(it)
        assert it["seconds"] >= 0 and it["done_s"] >= it["sent_s"] >= 0, it
        # the thread's CPU time is part of the tile's wall time (the two
        # clocks are read in nested order; their grain and rates)
        assert 0 <= it["cpu_s"] <= it["seconds"] * 1.001 + 1e-6, it
        assert (it["estimate"] is not None) == (s["mode"] == "hetero" and not it["fill"]), it
        workers = range(s["relays"] + 1, s["ranks"]) if s["ranks"] > 1 else [0]
        assert it["worker"] in workers, it
for t in range(s["tiles_total"]):
    tx, ty = t % cols * T, t // cols * T
    assert area.get(t) == min(T, W - tx) * min(T, H - ty), (t, area.get(t))
assert skipped == s["tiles_degenerate"], (skipped, s["tiles_degenerate"])
fill = [i["tile"] for i in sent if i["fill"]]
assert len(set(fill)) == s["tiles_filled"] and (s["mode"] == "hetero" or not fill), fill
assert all(f > i["tile"] for f in fill for i in items if not i["fill"]), "fill from the bottom up"
assert len(sent) == s["items_sent"] and sorted(i["order"] for i in sent) == list(range(len(sent)))
assert not sent or sum(i["cpu_s"] for i in sent) > 0, "no CPU time in the tile log"
assert sum(i["hits"] for i in items) == s["pixels_hit"] or s["mode"] == "hetero"
K = s["relays"]  # (static with relays: the k-th tile to relay k mod K, then its group)
def dealt_to(w):
    return w if K == 0 else 1 + (w - K - 1) % K
if schedule == "static" and s["ranks"] > 2:
    whole = sorted(sent, key=lambda i: i["tile"])
    children = K if K else s["ranks"] - 1
    assert all(dealt_to(i["worker"]) == k % children + 1 for k, i in enumerate(whole)), "static"
if schedule == "region" and s["ranks"] > 2 and K == 0:
    # each worker takes the tiles of its own band (tile t of T: worker t x W / T)
    # in raster order, in homo the first of them first (hetero's bands
    # become ready as the pass goes down: a worker below steals meanwhile)
    W = s["ranks"] - 1
    owner = lambda t: t * W // s["tiles_total"] + 1
    for w in range(1, s["ranks"]):
        mine = sorted((i for i in sent if i["worker"] == w and not i["fill"]),
                      key=lambda i: i["order"])  # (the fill's tiles go bottom up)
        own = [i["tile"] for i in mine if owner(i["tile"]) == w]
        assert own == sorted(own), ("region: own band out of order", w, own)
        assert s["mode"] != "homo" or not mine or owner(mine[0]["tile"]) == w, ("region: first tile", w)
if schedule == "tail" and s["tiles_sent"] > 2 * 2 * max(s["ranks"] - 1, 1) and s["tiles_filled"] == 0:
    assert any(i["piece"] > 0 for i in sent), "tail: no piece"  # (the fill may take the last tiles whole)
elif schedule != "tail" and s.get("pieces", 1) == 1:
    assert all(i["piece"] == 0 for i in sent), "pieces outside tail (and --pieces)"
EOF
}
if render st-h3 3 "$first" "${SZ[@]}" --mode homo --tile 8 --stats "$TMP/st-h3.json" &&
    check_stats "$TMP/st-h3.json" homo 3 2>"$TMP/st-h3.py"; then
    ok "stats JSON of homo K=3: every field, counts add up"
else
    bad "stats JSON of homo K=3 ($(tail -1 "$TMP/st-h3.py" 2>/dev/null))"
fi
if render st-s 0 "$first" "${SZ[@]}" --mode serial --stats "$TMP/st-s.json" &&
    check_stats "$TMP/st-s.json" serial 1 2>"$TMP/st-s.py"; then
    ok "stats JSON of serial: every field, counts add up"
else
    bad "stats JSON of serial ($(tail -1 "$TMP/st-s.py" 2>/dev/null))"
fi
if [ $have_cl = 1 ]; then
    if render st-x3 3 "$first" "${SZ[@]}" --mode hetero --tile 8 --stats "$TMP/st-x3.json" &&
        check_stats "$TMP/st-x3.json" hetero 3 2>"$TMP/st-x3.py"; then
        ok "stats JSON of hetero K=3: every field, counts add up"
    else
        bad "stats JSON of hetero K=3 ($(tail -1 "$TMP/st-x3.py" 2>/dev/null))"
    fi
fi
check "one summary line on stdout" test "$(wc -l <"$TMP/st-h3.out")" = 1

# ---- schedules: every one, both modes, 1 to 5 ranks ---------------------------------
modes=(homo)
[ $have_cl = 1 ] && modes+=(hetero)
for sched in raster cost static tail region; do
    for mode in "${modes[@]}"; do
        bad_ranks=""
        fill=() # (hetero: the scheduler alone; the batches below run with the fill)
        [ "$mode" = hetero ] && fill=(--fill off)
        # (hetero: 2, 3 and 5 ranks; 1 and 4 ranks of it run elsewhere in
        # the suites, and each of its renders opens the device)
        ranks_list=(1 2 3 4 5)
        [ "$mode" = hetero ] && ranks_list=(2 3 5)
        for np in "${ranks_list[@]}"; do
            name=sch-$sched-$mode-$np
            if ! render "$name" "$np" "$first" "${SZ[@]}" --mode "$mode" --tile 8 "${fill[@]}" \
                --schedule "$sched" --tile-log "$TMP/$name.jsonl" --stats "$TMP/$name.json"; then
                bad_ranks="$bad_ranks $np(exit:$(grep -m1 ': error: ' "$TMP/$name.err"))"
            elif ! same "$R" "$name"; then
                bad_ranks="$bad_ranks $np(pixels)"
            elif ! check_stats "$TMP/$name.json" "$mode" "$np" 2>"$TMP/$name.py" ||
                ! check_tile_log "$TMP/$name.jsonl" "$TMP/$name.json" "$sched" 2>>"$TMP/$name.py"; then
                bad_ranks="$bad_ranks $np($(tail -1 "$TMP/$name.py"))"
            fi
        done
        if [ -z "$bad_ranks" ]; then
            ok "--schedule $sched, $mode${fill:+ ${fill[*]}}, K=${ranks_list[*]}: == serial, tile log and stats consistent"
        else
            bad "--schedule $sched, $mode: K=$bad_ranks"
        fi
    done
done

# ---- batches: several items a TILE, one RESULT for them --------------------------
# batched FILE: more items than TILE messages, within the batch asked for.
batched() {
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); \
sys.exit(0 if j['batch'] == int(sys.argv[2]) and 0 < j['tile_messages'] < j['items_sent'] else 1)" "$@"
}
for sched in raster cost static tail region; do
    for mode in "${modes[@]}"; do
        name=bat-$sched-$mode
        if ! render "$name" 3 "$first" "${SZ[@]}" --mode "$mode" --tile 7 --batch 4 \
            --schedule "$sched" --tile-log "$TMP/$name.jsonl" --stats "$TMP/$name.json"; then
            bad "--batch 4 --schedule $sched, $mode, K=3 (exit: $(grep -m1 ': error: ' "$TMP/$name.err"))"
        elif ! same "$R" "$name"; then
            bad "--batch 4 --schedule $sched, $mode, K=3: pixels differ from serial"
        elif ! check_stats "$TMP/$name.json" "$mode" 3 2>"$TMP/$name.py" ||
            ! check_tile_log "$TMP/$name.jsonl" "$TMP/$name.json" "$sched" 2>>"$TMP/$name.py"; then
            bad "--batch 4 --schedule $sched, $mode, K=3: $(tail -1 "$TMP/$name.py")"
        elif ! batched "$TMP/$name.json" 4; then
            bad "--batch 4 --schedule $sched, $mode, K=3: not batched ($(grep -E '"(batch|tile_messages|items_sent)"' "$TMP/$name.json" | tr -d '\n ')"
        else
            ok "--batch 4 --schedule $sched, $mode, K=3, tile 7: == serial, fewer messages than items$([ "$mode" = hetero ] && echo " (with the fill: $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['tiles_filled'])" "$TMP/$name.json") tiles)")"
        fi
    done
done
# render_logged NAME NP MODE SCHEDULE WHAT ARGS...: a render with its stats
# and tile log that equals the serial image, its stats and log consistent;
# else one FAIL line saying WHAT and why, and a failure.
render_logged() {
    local name=$1 np=$2 mode=$3 sched=$4 what=$5
    shift 5
    if ! render "$name" "$np" "$first" "${SZ[@]}" --mode "$mode" --schedule "$sched" "$@" \
        --tile-log "$TMP/$name.jsonl" --stats "$TMP/$name.json"; then
        bad "$what (exit: $(grep -m1 ': error: ' "$TMP/$name.err"))"
    elif ! same "$R" "$name"; then
        bad "$what: pixels differ from serial"
    elif ! check_stats "$TMP/$name.json" "$mode" "$np" 2>"$TMP/$name.py" ||
        ! check_tile_log "$TMP/$name.jsonl" "$TMP/$name.json" "$sched" 2>>"$TMP/$name.py"; then
        bad "$what: $(tail -1 "$TMP/$name.py")"
    else
        return 0
    fi
    return 1
}
# ---- relays: a second level of masters (--relays, comm/relay.h) ----------------------
# Ranks 1 .. K relay: rank 0 deals them batches, they deal their workers;
# the image is the serial one, every item is computed by a worker (never a
# relay), the stats name the relays and list only the workers, and rank 0
# sends fewer TILE messages than the items, keeping 16 batches at a relay
# in homo (no estimates) and 8 in hetero (comm/protocol.h:
# proto_relay_depth, for groups of 16 workers or fewer as these).
relayed() { # relayed STATS K MODE: K relays, fewer messages than items
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); \
sys.exit(0 if j['relays'] == int(sys.argv[2]) and 0 < j['tile_messages'] < j['items_sent'] \
and j['relay_depth'] == (16 if sys.argv[3] == 'homo' else 8) else 1)" "$@"
}
for mode in "${modes[@]}"; do
    for cfg in "4 1 raster" "5 2 cost" "6 2 tail" "7 3 static"; do
        read -r np k sched <<<"$cfg"
        name=rel-$mode-$np-$k
        if ! render_logged "$name" "$np" "$mode" "$sched" "--relays $k, $mode, K=$np" \
            --tile 5 --relays "$k"; then
            : # (said)
        elif [ "$sched" != static ] && ! relayed "$TMP/$name.json" "$k" "$mode"; then
            bad "--relays $k, $mode, K=$np: not relayed ($(grep -E '"(relays|relay_depth|tile_messages|items_sent)"' "$TMP/$name.json" | tr -d '\n ')"
        else
            ok "--relays $k --schedule $sched, $mode, K=$np, tile 5: == serial, items on workers only, stats and tile log consistent"
        fi
    done
done
# A relay answers each batch as soon as its parts are done, not behind an
# older one still computing (comm/protocol.h): with worker 2 of relay 1
# slow (20 ms more a message, CSGTRACE_TEST_SLOW_WORKER), rank 0 takes
# answers to later batches first (answers_early > 0; in order it was 0
# whatever the workers did) and still puts each part where it belongs.
if CSGTRACE_TEST_SLOW_WORKER=2 render_logged rel-early 4 homo raster \
    "--relays 1, a slow worker" --tile 2 --relays 1; then
    if python3 -c "import json,sys; j=json.load(open(sys.argv[1])); \
sys.exit(0 if 0 < j['answers_early'] < j['tile_messages'] else 1)" "$TMP/rel-early.json"; then
        ok "--relays 1, worker 2 slow: answers out of order ($(grep -o '"answers_early": [0-9]*' "$TMP/rel-early.json")), == serial"
    else
        bad "--relays 1, worker 2 slow: no answer came early ($(grep -E '"(answers_early|tile_messages)"' "$TMP/rel-early.json" | tr -d '\n ')"
    fi
fi
# ---- pieces: tiles cut into work items from the start (--pieces) ---------------------
# Every tile goes as N pieces (the fill's too): the image is the serial
# one, the log's pieces partition each tile as schedule.c cuts it, the
# stats say N (a request cut no finer than a pixel).
pieced() { # pieced STATS LOG N: N pieces, each tile cut as schedule.c cuts it
    python3 - "$@" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
items = [json.loads(line) for line in open(sys.argv[2])]
n = int(sys.argv[3])
c = {1: 1, 4: 2, 16: 4, 64: 8}[n]
assert s["pieces"] == n, s["pieces"]
def spans(length):  # the non-empty cuts of an edge: ceil(length i / c)
    at = [(length * i + c - 1) // c for i in range(c + 1)]
    return sum(1 for i in range(c) if at[i + 1] > at[i])
per_tile = {}
for it in items:
    if not it["skipped"]:
        per_tile.setdefault(it["tile"], []).append(it)
for t, its in per_tile.items():  # (the fill's tiles too)
    w = sum(i["width"] for i in its if i["y"] == its[0]["y"])
    h = sum(i["height"] for i in its if i["x"] == its[0]["x"])
    assert len(its) == spans(w) * spans(h), (t, len(its), w, h)
    assert min(i["piece"] for i in its) >= 1, its
EOF
}
for mode in "${modes[@]}"; do
    for cfg in "3 0 raster 4 4" "5 2 cost 16 16" "4 0 tail 64 16"; do # (64: cuts of 8 > tile 7)
        read -r np k sched n cut <<<"$cfg"
        name=pcs-$mode-$np-$n
        if ! render_logged "$name" "$np" "$mode" "$sched" "--pieces $n, $mode, K=$np" \
            --tile 7 --relays "$k" --pieces "$n"; then
            : # (said)
        elif ! pieced "$TMP/$name.json" "$TMP/$name.jsonl" "$cut" 2>"$TMP/$name.py"; then
            bad "--pieces $n, $mode, K=$np: not cut as asked ($(tail -1 "$TMP/$name.py"))"
        else
            ok "--pieces $n --schedule $sched --relays $k, $mode, K=$np, tile 7: == serial, $cut pieces partition each tile"
        fi
    done
done
if "$BIN" render "$first" -o "$TMP/pcs-bad.pfm" --pieces 8 >/dev/null 2>"$TMP/pcs-bad.err"; then
    bad "--pieces 8 accepted"
elif [ $? = 2 ] && grep -q -- "--pieces: 1, 4, 16, 64 or auto, got 8" "$TMP/pcs-bad.err" && [ ! -e "$TMP/pcs-bad.pfm" ]; then
    ok "--pieces 8 refused (exit 2, says which values)"
else
    bad "--pieces 8: $(cat "$TMP/pcs-bad.err")"
fi
[ $have_cl = 1 ] && render_same "double hetero K=5 --relays 2 --batch 3 == serial" dbl-ref dbl-rel 5 \
    "$first" "${SZ[@]}" --mode hetero --tile 7 --precision double --relays 2 --batch 3
for mode in "${modes[@]}"; do # (a relay holding hundreds of parts deals several a message)
    render_same "$mode K=3 --relays 1 tile 2 --batch 32 == serial" "$R" "rel-many-$mode" 3 \
        "$first" "${SZ[@]}" --mode "$mode" --tile 2 --batch 32 --relays 1
done
MPIX="--mca btl tcp,self" render_same "homo K=5 --relays 2 over TCP == serial" "$R" m-rtcp 5 \
    "$first" "${SZ[@]}" --mode homo --tile 16 --relays 2
render rel-few 4 "$first" "${SZ[@]}" --mode homo --relays 2
rc=$?
check "--relays 2 with 3 workers: exit 2, one message, no image (got $rc)" \
    test $rc = 2 -a "$(error_lines rel-few)" = 1 -a ! -e "$TMP/rel-few.pfm"
CSGTRACE_TEST_FAIL_WORKER=3 render rel-fail 5 "$first" "${SZ[@]}" --mode homo --tile 8 --relays 2
rc=$?
check "a worker under a relay fails (K=5, --relays 2): exit 1, one message naming worker 3, no image (got $rc)" \
    test $rc = 1 -a "$(error_lines rel-fail)" = 1 -a "$(grep -c 'worker 3 failed' "$TMP/rel-fail.err")" = 1 \
    -a ! -e "$TMP/rel-fail.pfm"

render_same "double homo K=3 tile 7 --batch 3 == serial" dbl-ref dbl-bh3 3 "$first" "${SZ[@]}" \
    --mode homo --tile 7 --precision double --batch 3
[ $have_cl = 1 ] && render_same "double hetero K=3 tile 7 --batch 32 == serial" dbl-ref dbl-bx3 3 \
    "$first" "${SZ[@]}" --mode hetero --tile 7 --precision double --batch 32
MPIX="--mca btl tcp,self" render_same "homo K=3 --batch 4 over TCP == serial" "$R" m-btcp 3 \
    "$first" "${SZ[@]}" --mode homo --tile 16 --batch 4
if render bat-auto 3 "$first" "${SZ[@]}" --mode homo --tile 8 --stats "$TMP/bat-auto.json" &&
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); \
sys.exit(0 if j['batch'] == 1 and j['tile_messages'] == j['items_sent'] else 1)" "$TMP/bat-auto.json"; then
    ok "--batch auto with 2 workers: one item a message"
else
    bad "--batch auto with 2 workers: $(grep -E '"(batch|tile_messages|items_sent)"' "$TMP/bat-auto.json" | tr -d '\n ')"
fi
render bat-bad 0 "$first" "${SZ[@]}" --mode serial --batch 33
rc=$?
check "--batch 33 (over 32): exit 2, one message (got $rc)" test $rc = 2 -a "$(error_lines bat-bad)" = 1

# ---- failures ------------------------------------------------------------------
printf 'sphere { <0, 0, 0>, 1 \n  pigment { color rgb <1, 0, 0> }\n  @@@ }\n' >"$TMP/bad.pov"
render bad-h3 3 "$TMP/bad.pov" "${SZ[@]}" --mode homo
rc=$?
check "scene error under mpirun K=3: exit 2 (got $rc)" test $rc = 2
check "scene error under mpirun K=3: one message" test "$(error_lines bad-h3)" = 1
check "scene error under mpirun K=3: no image" test ! -e "$TMP/bad-h3.pfm"

CSGTRACE_TEST_FAIL_WORKER=2 render fail-h3 3 "$first" "${SZ[@]}" --mode homo --tile 8
rc=$?
check "worker 2 fails (homo K=3): exit 1 (got $rc)" test $rc = 1
check "worker 2 fails (homo K=3): one message naming worker 2" \
    test "$(error_lines fail-h3)" = 1 -a "$(grep -c 'worker 2' "$TMP/fail-h3.err")" = 1
check "worker 2 fails (homo K=3): no image" test ! -e "$TMP/fail-h3.pfm"

CSGTRACE_TEST_FAIL_WORKER=1 render fail-h2 2 "$first" "${SZ[@]}" --mode homo --tile 100
rc=$?
check "the only worker fails (homo K=2): exit 1, no image (got $rc)" \
    test $rc = 1 -a ! -e "$TMP/fail-h2.pfm"

# A worker that breaks the protocol (tests/rogue_worker.c, MPMD rank 1):
# every crafted answer is refused before it is used, with one message, exit
# 1 and no image; an oversized one is never received (link_recv's limit).
ROGUE=$ROOT/build/tests/rogue_worker
# To EXR the answers are RGB floats (12 bytes a pixel), to PNG the file's
# bytes (3: comm/pixels.h); each well-sized answer is sized for its format.
# (The header's fields, index and tag, are checked once: they do not depend
# on the format.)
for ext in exr png; do
    rogue_modes=(big short index tag pixels)
    [ "$ext" = png ] && rogue_modes=(big short pixels)
    for mode in "${rogue_modes[@]}"; do
        if [ ! -x "$ROGUE" ]; then
            bad "rogue worker ($mode): $ROGUE is not built"
            continue
        fi
        out=$TMP/rogue-$mode.$ext
        ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} timeout 120 "${MPIRUN[@]}" -np 1 "$BIN" render \
            "$first" "${SZ[@]}" --mode homo -o "$out" : -np 1 "$ROGUE" "$mode" \
            >"$TMP/rogue-$mode.out" 2>"$TMP/rogue-$mode.err"
        rc=$?
        check "rogue worker ($mode, to $ext): exit 1, one message naming worker 1, no image (got $rc)" \
            test $rc = 1 -a "$(error_lines "rogue-$mode")" = 1 \
            -a "$(grep -c 'worker 1' "$TMP/rogue-$mode.err")" = 1 -a ! -e "$out"
    done
    for mode in part one; do
        [ -x "$ROGUE" ] || continue
        out=$TMP/rogue-$mode.$ext
        ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} timeout 120 "${MPIRUN[@]}" -np 1 "$BIN" render \
            "$first" "${SZ[@]}" --mode homo --tile 8 --batch 4 -o "$out" \
            : -np 1 "$ROGUE" "$mode" >"$TMP/rogue-$mode.out" 2>"$TMP/rogue-$mode.err"
        rc=$?
        check "rogue worker, batch of 4 ($mode, to $ext): exit 1, one message naming worker 1, no image (got $rc)" \
            test $rc = 1 -a "$(error_lines "rogue-$mode")" = 1 \
            -a "$(grep -c 'worker 1' "$TMP/rogue-$mode.err")" = 1 -a ! -e "$out"
    done
done
# rogue_refused NAME WORKER DESCRIPTION RELAYS RENDER-ARGS... -- ROGUE-MODE:
# the render of $first with a rogue worker beside RELAYS relays ends with
# exit 1, one message naming worker WORKER and no image.  (A relay that
# ends the job with MPI_Abort, as on a message too large to take, races
# mpirun's SIGTERM to rank 0, which may have rendered the lost items itself
# and written the image first: then its line says the files are kept, and
# they are.  The rogue's own line when its relay's abort beats mpirun's
# SIGTERM to it, about 1 run in 100 on a loaded machine, is not the
# render's.)
rogue_refused() {
    local name=$1 worker=$2 what=$3 relays=$4 out=$TMP/$1.png rc kept
    shift 4
    local args=() mode
    while [ "$1" != -- ]; do args+=("$1"); shift; done
    mode=$2
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} timeout 120 "${MPIRUN[@]}" -np $((relays + 1)) \
        "$BIN" render "$first" "${SZ[@]}" --mode homo --relays "$relays" "${args[@]}" -o "$out" \
        : -np 1 "$ROGUE" "$mode" >"$TMP/$name.out" 2>"$TMP/$name.err"
    rc=$?
    kept=$(grep -c 'after the render had finished: its files are kept' "$TMP/$name.err")
    grep -v ": error: worker $worker: the master is gone; exiting\$" "$TMP/$name.err" \
        >"$TMP/$name.master.err"
    check "$what: exit 1, one message naming worker $worker, no image (got $rc)" \
        test $rc = 1 -a "$(error_lines "$name.master")" = 1 \
        -a "$(grep -c "worker $worker" "$TMP/$name.master.err")" = 1 \
        -a \( ! -e "$out" -o "$kept" = 1 \)
}
# Compressed results (--compress on): a frame longer than its pixels
# could compress to, one that is not Zstandard, one that decompresses past
# its tile: each refused, directly and through a relay (which forwards the
# parts whose size fits, rank 0's store thread decompressing them).
for mode in zbound zcorrupt zlong; do
    [ -x "$ROGUE" ] || continue
    for relays in 0 1; do
        rogue_refused "rogue-z$relays-$mode" $((relays + 1)) \
            "rogue worker, compressed ($mode, relays $relays)" $relays --compress on -- "$mode"
    done
done
# The same rogue under a relay (ranks 0, 1: csgtrace with --relays 1; rank
# 2: the rogue, relay 1's only worker): the relay refuses its answer.
# Tile 2 and --batch 32: the relay holds hundreds of parts and deals the
# rogue several a message (part, one).
for mode in big short index tag pixels part one; do
    [ -x "$ROGUE" ] || continue
    rogue_refused "rogue-rel-$mode" 2 "rogue worker under a relay ($mode)" 1 --tile 2 --batch 32 \
        -- "$mode"
done

if [ $have_cl = 1 ]; then
    CSGTRACE_TEST_FAIL_WORKER=1 render fail-x3 3 "$first" "${SZ[@]}" --mode hetero --tile 4
    rc=$?
    check "worker 1 fails (hetero K=3): exit 1, one message, no image (got $rc)" \
        test $rc = 1 -a "$(error_lines fail-x3)" = 1 -a ! -e "$TMP/fail-x3.pfm"

    CSGTRACE_CL_DEVICE=no-such-device-xyz render clbad-x3 3 "$first" "${SZ[@]}" --mode hetero
    rc=$?
    check "OpenCL failure (hetero K=3): exit 1, one message, no image (got $rc)" \
        test $rc = 1 -a "$(error_lines clbad-x3)" = 1 -a ! -e "$TMP/clbad-x3.pfm"
fi

# A scene whose ray tree doubles at every level (a mirror-glass shell around
# a glass ball, max_trace_level 256, adc_bailout 0) ends: the ray budget
# stops each pixel's tree at the same ray in every mode; the stats count the
# pixels that met it and one warning line says so.
cat >"$TMP/runaway.pov" <<'POV'
global_settings { max_trace_level 256 adc_bailout 0 }
camera { location <0, 0, -5> look_at 0 }
light_source { <3, 4, -6> color rgb 1 }
sphere { 0, 2 hollow pigment { rgbf <1, 1, 1, 0.9> } finish { reflection 0.9 } interior { ior 1.5 } }
sphere { 0, 1 pigment { rgbf <1, 1, 1, 0.9> } finish { reflection 0.5 } interior { ior 1.3 } }
POV
budget_ok() { # budget_ok NAME BUDGET: a warning line, and the stats' count
    [ "$(grep -c 'met their ray budget' "$TMP/$1.err")" = 1 ] &&
        python3 - "$TMP/$1.json" "$2" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
r = j["rays"]
px = j["pixels_over_budget"]
budget = int(sys.argv[2])
# each pixel traces at most its budget of reflected and refracted rays
sys.exit(0 if j["max_rays_per_pixel"] == budget and 0 < px <= j["pixels"]
         and r["reflected"] + r["refracted"] <= j["pixels"] * budget else 1)
PY
}
timeout 60 "$BIN" render "$TMP/runaway.pov" --width 16 --height 12 --mode serial \
    --stats "$TMP/runaway-s.json" -o "$TMP/runaway-s.pfm" >/dev/null 2>"$TMP/runaway-s.err"
check "runaway ray tree: serial ends with the default budget, counted and said once" \
    budget_ok runaway-s 4096
render runaway-b 0 "$TMP/runaway.pov" --width 16 --height 12 --mode serial --max-rays-per-pixel 64 \
    --stats "$TMP/runaway-b.json"
check "runaway ray tree: --max-rays-per-pixel 64 counted" budget_ok runaway-b 64
for np in 3; do
    render_same "runaway ray tree, budget 64: homo K=$np == serial" runaway-b runaway-h$np $np \
        "$TMP/runaway.pov" --width 16 --height 12 --mode homo --max-rays-per-pixel 64
    if [ $have_cl = 1 ]; then
        render_same "runaway ray tree, budget 64: hetero K=$np == serial" runaway-b runaway-x$np $np \
            "$TMP/runaway.pov" --width 16 --height 12 --mode hetero --max-rays-per-pixel 64
    fi
done

# ---- one copy of the scene per node --------------------------------------------
# scene_ranks NAME SHARED PRIVATE: the stats' counts of ranks reading the
# node's one copy and of ranks holding their own.
scene_ranks() {
    python3 -c "import json,sys; j=json.load(open(sys.argv[1]));
sys.exit(0 if (j['scene_shared_ranks'], j['scene_private_ranks']) == (int(sys.argv[2]), int(sys.argv[3])) else 1)" \
        "$TMP/$1.json" "$2" "$3"
}
render_same "one scene a node: homo K=4 == serial" "$R" shm-h4 4 "$first" "${SZ[@]}" \
    --mode homo --tile 8 --stats "$TMP/shm-h4.json"
check "one scene a node: homo K=4, all 4 ranks read the master's copy" scene_ranks shm-h4 4 0
CSGTRACE_NODE_SCENE=off render_same "CSGTRACE_NODE_SCENE=off: homo K=3 == serial" "$R" shm-off 3 \
    "$first" "${SZ[@]}" --mode homo --tile 8 --stats "$TMP/shm-off.json"
check "CSGTRACE_NODE_SCENE=off: each of the 3 ranks holds its own copy" scene_ranks shm-off 0 3
render_same "one scene a node: homo K=5 --relays 1 == serial" "$R" shm-r1 5 "$first" "${SZ[@]}" \
    --mode homo --tile 8 --relays 1 --stats "$TMP/shm-r1.json"
check "one scene a node: the relay and its group read the master's copy" scene_ranks shm-r1 5 0
# Nodes of 2 ranks pretended (CSGTRACE_TEST_NODE_RANKS): ranks 2 and 4
# lead their nodes, receive the scene over the leaders' communicator (or,
# under --enable-recovery, sent one by one), check it and tell rank 3,
# which maps rank 2's copy; rank 4 is alone on its node (its own copy).
CSGTRACE_TEST_NODE_RANKS=2 render_same "nodes of 2 ranks: homo K=5 == serial" "$R" shm-n2 5 \
    "$first" "${SZ[@]}" --mode homo --tile 8 --stats "$TMP/shm-n2.json"
check "nodes of 2 ranks: 4 ranks read their leader's copy, rank 4 (alone) its own" \
    scene_ranks shm-n2 4 1
if [ $have_cl = 1 ]; then
    CSGTRACE_TEST_NODE_RANKS=2 MPIX="--enable-recovery" render_same \
        "nodes of 2 ranks, --enable-recovery: hetero K=5 == serial" "$R" shm-n2x 5 "$first" \
        "${SZ[@]}" --mode hetero --tile 8 --stats "$TMP/shm-n2x.json"
    check "nodes of 2 ranks, --enable-recovery: 4 ranks read their leader's copy, rank 4 its own" \
        scene_ranks shm-n2x 4 1
fi
# Rank 2, a leader, dies before the scene (--enable-recovery): rank 3
# would wait for its word for ever; the master writes it off with it.
CSGTRACE_TEST_NODE_RANKS=2 CSGTRACE_TEST_KILL_RANK=2 CSGTRACE_TEST_KILL_AT=scene \
    CSGTRACE_TEST_KILL_AFTER=0 MPIX="--enable-recovery" render_same \
    "nodes of 2 ranks, leader 2 killed before the scene: homo K=5 == serial" "$R" shm-kill 5 \
    "$first" "${SZ[@]}" --mode homo --tile 8 --stats "$TMP/shm-kill.json"
leader_lost() {
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if j['workers_lost'] == 2 else 1)" \
        "$TMP/shm-kill.json" && grep -q "worker 3 lost (its node's leader, rank 2, is gone" \
        "$TMP/shm-kill.err"
}
check "nodes of 2 ranks, leader 2 killed: rank 3 written off with it (workers_lost 2, one line)" \
    leader_lost
render shm-s 0 "$first" "${SZ[@]}" --mode serial --stats "$TMP/shm-s.json"
check "serial: one rank, its own copy" scene_ranks shm-s 0 1

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
