#!/usr/bin/env bash
# e2e_paging.sh — a worker's scene below a memory budget (--scene-memory,
# workers/pager.h): pages of the BVH fetched from rank 0 on demand, an LRU
# or FIFO cache, hetero items fetching their hit records' pages first.
#   - at a budget that holds the resident part and two pages (so that
#     nearly every item evicts), the image is the in-memory render's bit
#     for bit: serial, homo and hetero (2 workers), float and double, LRU
#     and FIFO, the prefetch on and off; and the stats show the paging
#     happened (faults, evictions, the pages' bytes) and stayed within the
#     budget between items (the most over it is the peak's excess);
#   - hetero with the pass's records prefetches pages (prefetched > 0),
#     without the prefetch none;
#   - --page-fetch get (the default) reads the pages one-sided from rank
#     0's window (rank 0 answers no ask); ask: rank 0 answers each request
#     (homo float, hetero double), the same images; where MPI cannot open
#     the window, asked for;
#   - --page-prefetch shadows: the shadow rays' pages come before the
#     shading too: an opaque scene's rays fault at most a twentieth as
#     often as without a prefetch, under half as often as with `on`;
#   - the tile log has each item's page faults and wait;
#   - homes (--page-home spread, 3 workers): each worker holds a third of
#     the pages and answers the others' asks; the image is the in-memory
#     one (homo and hetero, float and double), rank 0 sent no more than
#     the pages once (each to its home, when first needed), the workers
#     answered one another, the cache evicted; auto leaves it to rank 0
#     with 3 workers (it spreads from 128: test_pager);
#   - a budget below the resident part, --scene-memory with --relays, and
#     --page-home spread where a share does not fit are refused with a
#     message (exit 2), no image written.
# Usage: tests/e2e_paging.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

mpi_sandbox
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$PWD/build/pocl-cache}
MPI=(timeout -s KILL 120 mpirun --bind-to none --oversubscribe -np 3)
SZ=(--width 64 --height 48 --tile 8)
SCENE=$T/spheres.pov
"$BIN" gen spheres --count 1000 --occupancy 0.6 --seed 11 --width 64 --height 48 \
    --materials opaque,reflective,transparent -o "$SCENE" >/dev/null || ko "gen"

# The in-memory images, and the budget: the resident part and two pages.
for prec in float double; do
    "$BIN" render "$SCENE" "${SZ[@]}" --precision $prec -o "$T/full-$prec.pfm" >/dev/null 2>&1 ||
        ko "in-memory render ($prec)"
done
# (a probe at 1 MB: pages of 16 KiB, the smallest, whatever the precision)
declare -A BUDGET_MB RESIDENT
for prec in float double; do
    "$BIN" render "$SCENE" "${SZ[@]}" --precision $prec -o "$T/probe.pfm" --scene-memory 1 \
        --stats "$T/probe-$prec.json" >/dev/null 2>&1 || ko "probe render ($prec)"
    read -r resident page pages < <(python3 -c "import json,sys; m=json.load(open(sys.argv[1]))['scene_memory']; print(m['resident_bytes'], m['page_bytes'], m['pages'])" "$T/probe-$prec.json")
    [ "${pages:-0}" -ge 8 ] && ok "$prec: the scene has $pages pages of $page bytes" ||
        ko "$prec: the scene has too few pages to page (${pages:-none})"
    RESIDENT[$prec]=${resident:-0}
    BUDGET_MB[$prec]=$(python3 -c "print((${resident:-0} + 2 * 16384 + 4096) / 1e6)")
done

# paged NAME PREC RANKS-PREFIX... -- ARGS: renders with the budget, checks
# the image and the stats.
paged() {
    local name=$1 prec=$2
    shift 2
    local out=$T/$name.pfm
    "$@" "$BIN" render "$SCENE" "${SZ[@]}" --precision $prec --scene-memory "${BUDGET_MB[$prec]}" \
        -o "$out" --stats "$out.json" --tile-log "$out.log" "${EXTRA[@]}" >/dev/null 2>"$out.err" ||
        { ko "$name: render failed: $(head -c 300 "$out.err")"; return; }
    same "$T/full-$prec.pfm" "$out" && ok "$name: the in-memory image, bit for bit" ||
        ko "$name: the image differs from the in-memory render"
    json "$out.json" "j['paging']['faults'] > 0 and j['paging']['evictions'] > 0 and j['paging']['bytes'] > 0 and j['paging']['install_s'] > 0" &&
        ok "$name: pages were faulted in and evicted" || ko "$name: no paging happened"
    json "$out.json" "j['paging']['over_budget_bytes'] == max(0, j['paging']['peak_bytes'] - j['scene_memory']['budget_bytes'])" &&
        ok "$name: within the budget between items (peak $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['paging']['peak_bytes'])" "$out.json"))" ||
        ko "$name: the budget's accounting does not add up"
}

EXTRA=()
paged serial-float float
paged serial-double double
EXTRA=(--mode homo)
paged homo-float float "${MPI[@]}"
paged homo-double double "${MPI[@]}"
json "$T/homo-float.pfm.json" "j['schedule'] == 'region'" &&
    ok "homo with --scene-memory: the region schedule by default" || ko "homo paged: not the region schedule"
EXTRA=(--mode homo --page-policy fifo)
paged homo-fifo float "${MPI[@]}"
EXTRA=(--mode hetero --pass always --fill off)
paged hetero-float float "${MPI[@]}"
json "$T/hetero-float.pfm.json" "j['paging']['prefetched'] > 0" &&
    ok "hetero: the hit records' pages were prefetched" || ko "hetero: nothing prefetched"
# --page-fetch get (the default): the workers read rank 0's blob through
# an MPI window, rank 0 answers no ask; ask: rank 0 answers each request.
json "$T/homo-float.pfm.json" "j['scene_memory']['fetch'] == 'get' and j['scene_memory']['asks_answered'] == 0 and j['paging']['requests'] > 0" &&
    ok "homo: pages read one-sided (--page-fetch get), rank 0 answered no ask" ||
    ko "homo: the pages were not read one-sided"
EXTRA=(--mode homo --page-fetch ask)
paged homo-ask float "${MPI[@]}"
json "$T/homo-ask.pfm.json" "j['scene_memory']['fetch'] == 'ask' and j['scene_memory']['asks_answered'] == j['paging']['requests'] > 0" &&
    ok "homo, --page-fetch ask: rank 0 answered every request" || ko "homo, ask: rank 0's answers do not add up"
EXTRA=(--mode hetero --pass always --fill off --page-fetch ask)
paged hetero-ask double "${MPI[@]}"
# Where MPI cannot open the window (shared memory without cross-memory
# attach: Open MPI's osc/rdma refuses it), every rank learns it and the
# pages are asked for: the same image.
EXTRA=(--mode homo)
paged homo-nowindow float env OMPI_MCA_btl_vader_single_copy_mechanism=none "${MPI[@]}"
json "$T/homo-nowindow.pfm.json" "j['scene_memory']['fetch'] == 'ask' and j['scene_memory']['asks_answered'] > 0" &&
    ok "homo, no window to open: the pages were asked for" || ko "homo, no window: not asked for"
EXTRA=(--mode hetero --pass always --fill off --page-prefetch off)
paged hetero-noprefetch float "${MPI[@]}"
json "$T/hetero-noprefetch.pfm.json" "j['paging']['prefetched'] == 0" &&
    ok "hetero, --page-prefetch off: nothing prefetched" || ko "hetero: prefetched though off"
EXTRA=(--mode hetero --pass always --fill off)
paged hetero-double double "${MPI[@]}"
# The shadow rays' pages (--page-prefetch shadows; workers/shade.c,
# prefetch_shadow_pages): in a scene of opaque spheres (primary and shadow
# rays only) each hit's segment to each light is walked above the pages
# and their pages come in one request before the shading, so next to no
# ray faults (the primary rays' prefetch alone, `on`, leaves a quarter of
# the pages to faults here); the same image every way.
OPAQUE=$T/opaque.pov
"$BIN" gen spheres --count 1000 --occupancy 0.6 --seed 11 --width 64 --height 48 \
    --materials opaque -o "$OPAQUE" >/dev/null || ko "gen opaque"
"$BIN" render "$OPAQUE" "${SZ[@]}" -o "$T/opaque-full.pfm" --scene-memory 1 \
    --stats "$T/opaque-probe.json" >/dev/null 2>&1 || ko "opaque: probe render"
OPAQUE_MB=$(python3 -c "import json,sys; m=json.load(open(sys.argv[1]))['scene_memory']; print((m['resident_bytes'] + 2 * 16384 + 4096) / 1e6)" "$T/opaque-probe.json")
for pf in shadows on off; do
    "${MPI[@]}" "$BIN" render "$OPAQUE" "${SZ[@]}" --mode homo --scene-memory "$OPAQUE_MB" \
        --page-prefetch $pf -o "$T/opaque-$pf.pfm" --stats "$T/opaque-$pf.json" >/dev/null 2>&1 ||
        ko "opaque, prefetch $pf: render failed"
    same "$T/opaque-full.pfm" "$T/opaque-$pf.pfm" && ok "opaque, prefetch $pf: the in-memory image" ||
        ko "opaque, prefetch $pf: the image differs"
done
python3 -c "
import json, sys
sh, on, off = (json.load(open(f)) for f in sys.argv[1:4])
f = [j['paging']['faults'] for j in (sh, on, off)]
print(*f)
sys.exit(0 if f[2] > 0 and 20 * f[0] <= f[2] and 2 * f[0] < f[1] and
         sh['scene_memory']['prefetch_shadows'] and not on['scene_memory']['prefetch_shadows'] else 1)" \
    "$T/opaque-shadows.json" "$T/opaque-on.json" "$T/opaque-off.json" >"$T/opaque.faults" &&
    ok "opaque: the shadow rays' pages prefetched (faults shadows / on / off: $(tr '\n' ' ' <"$T/opaque.faults"))" ||
    ko "opaque: the shadow rays still fault (faults shadows / on / off: $(tr '\n' ' ' <"$T/opaque.faults"))"

python3 -c "
import json, sys
items = [json.loads(l) for l in open(sys.argv[1])]
sys.exit(0 if items and all('page_faults' in i and 'page_wait_s' in i for i in items)
         and sum(i['page_faults'] for i in items) > 0 else 1)" "$T/homo-float.pfm.log" &&
    ok "the tile log has each item's page faults" || ko "the tile log lacks page faults"

# The page trace ($CSGTRACE_PAGE_TRACE: the simulator's input): one line an
# item in each worker's file, every tile once, the pages the stats count.
# trace_check NAME KIND FILES...: the grid's 48 tiles of kind KIND, as many
# pages named as the stats' touches, at least the prefetched ones marked.
trace_check() {
    local name=$1 kind=$2
    shift 2
    python3 - "$T/$name.pfm.json" "$kind" "$@" <<'PY' && ok "$name: the page trace has every item's pages" || ko "$name: the page trace does not match the render"
import json, sys
stats = json.load(open(sys.argv[1]))["paging"]
kind, rects, named, marked = sys.argv[2], set(), 0, 0
for path in sys.argv[3:]:
    for line in open(path):
        f = line.split()
        k, x, y, w, h, n = f[0], *map(int, f[1:6])
        pages = list(map(int, f[6:]))
        assert k == kind and len(pages) == n and (x, y) not in rects, line
        assert len(set(p if p >= 0 else -1 - p for p in pages)) == n, line
        rects.add((x, y))
        named += n
        marked += sum(p < 0 for p in pages)
assert rects == {(x, y) for x in range(0, 64, 8) for y in range(0, 48, 8)}, len(rects)
assert named == stats["touches"] and marked >= stats["prefetched"] > 0, (named, marked, stats)
PY
}
EXTRA=(--mode homo)
paged homo-traced float env CSGTRACE_PAGE_TRACE="$T/homo.trace" "${MPI[@]}"
trace_check homo-traced T "$T/homo.trace.1" "$T/homo.trace.2"
EXTRA=(--mode hetero --pass always --fill off)
paged hetero-traced float env CSGTRACE_PAGE_TRACE="$T/hetero.trace" "${MPI[@]}"
trace_check hetero-traced S "$T/hetero.trace.1" "$T/hetero.trace.2"
EXTRA=()
paged serial-traced float env CSGTRACE_PAGE_TRACE="$T/serial.trace"
trace_check serial-traced T "$T/serial.trace.0"

# Homes: 3 workers (-np 4), a budget of the resident part and 0.6 of the
# pages: a share (a third, about) fits in two thirds of it, the rest is
# the cache, smaller than the two thirds a worker fetches from the others.
MPI4=(timeout -s KILL 120 mpirun --bind-to none --oversubscribe -np 4)
declare -A HOME_MB
for prec in float double; do
    HOME_MB[$prec]=$(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); r=j['scene_memory']['resident_bytes']; print((r + 0.6 * (j['blob_bytes'] - r)) / 1e6)" "$T/probe-$prec.json")
done
# spread NAME PREC HOME ARGS...: a 3-worker render at that budget
spread() {
    local name=$1 prec=$2 home=$3
    shift 3
    local out=$T/$name.pfm
    "${MPI4[@]}" "$BIN" render "$SCENE" "${SZ[@]}" --precision $prec --scene-memory "${HOME_MB[$prec]}" \
        --page-home "$home" -o "$out" --stats "$out.json" "$@" >/dev/null 2>"$out.err" ||
        { ko "$name: render failed: $(head -c 300 "$out.err")"; return 1; }
    same "$T/full-$prec.pfm" "$out" && ok "$name: the in-memory image, bit for bit" ||
        ko "$name: the image differs from the in-memory render"
}
for prec in float double; do
    for mode in homo hetero; do
        args=(--mode $mode)
        [ $mode = hetero ] && args+=(--pass always --fill off)
        spread spread-$mode-$prec $prec spread "${args[@]}" || continue
        json "$T/spread-$mode-$prec.pfm.json" "j['scene_memory']['homes'] == 3 and 0 < j['scene_memory']['bytes_served'] <= j['blob_bytes'] - j['scene_memory']['resident_bytes']" &&
            ok "spread-$mode-$prec: rank 0 sent each page once at most, to its home" ||
            ko "spread-$mode-$prec: rank 0 served other than the homes' shares"
        json "$T/spread-$mode-$prec.pfm.json" "j['paging']['served'] > 0 and j['paging']['served_bytes'] > 0 and j['paging']['faults'] > 0 and j['paging']['evictions'] > 0 and j['paging']['over_budget_bytes'] == max(0, j['paging']['peak_bytes'] - j['scene_memory']['budget_bytes'])" &&
            ok "spread-$mode-$prec: the workers answered one another, the cache evicted" ||
            ko "spread-$mode-$prec: no page went from worker to worker"
    done
done
spread spread-auto float auto --mode homo &&
    json "$T/spread-auto.pfm.json" "j['scene_memory']['homes'] == 0" &&
    ok "--page-home auto with 3 workers: rank 0 serves (spread from 128)" || ko "--page-home auto: spread with 3 workers"
spread spread-master float master --mode homo &&
    json "$T/spread-master.pfm.json" "j['scene_memory']['homes'] == 0 and j['paging']['served'] == 0" &&
    ok "--page-home master: rank 0 serves every page" || ko "--page-home master: pages served by workers"
json "$T/homo-float.pfm.json" "j['scene_memory']['homes'] == 0" &&
    ok "--page-home auto at two pages' budget: rank 0 serves" || ko "auto spread a share that does not fit"

# Refusals.
low=$(python3 -c "print((${RESIDENT[float]} - 1000) / 1e6)")
"$BIN" render "$SCENE" "${SZ[@]}" --scene-memory "$low" -o "$T/low.pfm" >/dev/null 2>"$T/low.err"
rc=$?
[ $rc -eq 2 ] && grep -q "below the scene's resident part" "$T/low.err" && [ ! -e "$T/low.pfm" ] &&
    ok "a budget below the resident part: refused (exit 2)" ||
    ko "a budget below the resident part: rc $rc, $(head -c 200 "$T/low.err")"
timeout -s KILL 120 mpirun --bind-to none --oversubscribe -np 5 "$BIN" render "$SCENE" "${SZ[@]}" \
    --mode homo --relays 2 --scene-memory 1000 -o "$T/relays.pfm" >/dev/null 2>"$T/relays.err"
rc=$?
[ $rc -eq 2 ] && grep -q "does not apply with --relays" "$T/relays.err" && [ ! -e "$T/relays.pfm" ] &&
    ok "--scene-memory with --relays: refused (exit 2)" ||
    ko "--scene-memory with --relays: rc $rc, $(head -c 200 "$T/relays.err")"
"${MPI4[@]}" "$BIN" render "$SCENE" "${SZ[@]}" --mode homo --scene-memory "${BUDGET_MB[float]}" \
    --page-home spread -o "$T/nohome.pfm" >/dev/null 2>"$T/nohome.err"
rc=$?
[ $rc -eq 2 ] && grep -q "page-home spread: a worker's share" "$T/nohome.err" && [ ! -e "$T/nohome.pfm" ] &&
    ok "--page-home spread where a share does not fit: refused (exit 2)" ||
    ko "--page-home spread where a share does not fit: rc $rc, $(head -c 200 "$T/nohome.err")"

e2e_finish
