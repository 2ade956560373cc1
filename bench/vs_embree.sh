#!/usr/bin/env bash
# bench/vs_embree.sh — csgtrace's primary rays against Embree's rtcIntersect1,
# one core, the same rays at the same spheres.
#
#   bench/vs_embree.sh
#
# Scenes: `csgtrace gen spheres --count N --occupancy 0.5 --seed 1` for N in
# COUNTS (default "1000 10000 100000"), framed at SIZE x SIZE (default
# 384; generating the 100 000-sphere scene takes about a minute, once: it
# is kept in the work folder).  For each, build/bench/primary_rays (the
# engine's trace_primary over the image, csgtrace's float build) exports
# the spheres and the camera, and build/bench/embree_primary traces the
# same rays in Embree 3 (RTC_GEOMETRY_TYPE_SPHERE_POINT, default build
# quality, rtcIntersect1 a ray).  ROUNDS (default 5) interleaved rounds,
# csgtrace first in odd rounds; each program reports the median of
# PASSES (default 5) timed passes after one untimed one.  Both report their
# hit counts: they must agree to within 0.01 % of the rays (grazing rays
# may round either way), else the run stops.
#
# Rows go to $BENCH_OUT/vs_embree.csv (started afresh); then
# bench/speed_report.py prints Mrays/s of each and their ratio per round.
# Numbers from the programs' JSON are read by a parser and passed on as
# data, never evaluated.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${CSGTRACE:-$ROOT/build/csgtrace}
PRIMARY=$ROOT/build/bench/primary_rays
EMBREE=$ROOT/build/bench/embree_primary
COUNTS=${COUNTS:-1000 10000 100000}
SIZE=${SIZE:-384}
ROUNDS=${ROUNDS:-5}
PASSES=${PASSES:-5}
OUT=${BENCH_OUT:-$ROOT/bench/results}
WORK=${BENCH_WORK:-$ROOT/build/bench}/embree
COLLECT=(python3 "$ROOT/bench/collect.py")
CSV="$OUT/vs_embree.csv"

# The 1-minute load average: this machine is shared, and the tables say how busy it was.
loadavg() { cut -d' ' -f1 /proc/loadavg; }
die() { echo "bench/vs_embree.sh: $*" >&2; exit 1; }
for b in "$BIN" "$PRIMARY" "$EMBREE"; do
    [ -x "$b" ] || die "$b not found: run 'make bench-speed' (it installs libembree-dev)"
done
[[ "$ROUNDS" =~ ^[1-9][0-9]{0,2}$ && "$PASSES" =~ ^[1-9][0-9]{0,2}$ ]] || die "ROUNDS, PASSES: 1 to 999"
[[ "$SIZE" =~ ^[1-9][0-9]{0,4}$ ]] || die "SIZE must be a pixel count"
for n in $COUNTS; do [[ "$n" =~ ^[1-9][0-9]{0,8}$ ]] || die "COUNTS must hold sphere counts"; done
mkdir -p "$OUT" "$WORK"

# The JSON object a helper printed, as key=value words (numbers only).
json_kv() {
    python3 - "$1" <<'EOF'
import json, sys
for k, v in json.load(open(sys.argv[1])).items():
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        print(f"{k}={v}")
EOF
}
json_get() { python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"; }

COMMIT=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
CPU=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1 | tr -s ' ,' ' ')
EMBREE_VERSION=$(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo unknown)

rm -f "$CSV"
for n in $COUNTS; do
    sc="$WORK/spheres-n$n-o0.5-s1-$SIZE.pov"
    if [ ! -s "$sc" ]; then
        echo "== generating $n spheres"
        "$BIN" gen spheres --count "$n" --occupancy 0.5 --seed 1 --width "$SIZE" --height "$SIZE" \
            -o "$sc" >/dev/null || die "gen failed"
    fi
    spheres="$WORK/spheres-n$n.txt"
    "$PRIMARY" "$sc" --width "$SIZE" --height "$SIZE" --repeat 1 --export-spheres "$spheres" \
        >"$WORK/csg.json" || die "primary_rays failed on $sc"
    echo "== vs_embree $n spheres at ${SIZE}x$SIZE, $ROUNDS rounds of $PASSES passes"
    common=(cpu="$CPU" cores="$(nproc)" commit="$COMMIT" embree_version="$EMBREE_VERSION" count="$n"
            width="$SIZE" height="$SIZE")
    for r in $(seq 1 "$ROUNDS"); do
        order="csgtrace embree"
        [ $((r % 2)) -eq 0 ] && order="embree csgtrace"
        for prog in $order; do
            if [ "$prog" = csgtrace ]; then
                "$PRIMARY" "$sc" --width "$SIZE" --height "$SIZE" --repeat "$PASSES" \
                    >"$WORK/csg.json" || die "primary_rays failed on $sc"
                mapfile -t kv < <(json_kv "$WORK/csg.json")
            else
                "$EMBREE" "$spheres" --repeat "$PASSES" >"$WORK/embree.json" \
                    || die "embree_primary failed on $spheres"
                mapfile -t kv < <(json_kv "$WORK/embree.json")
            fi
            "${COLLECT[@]}" append-kv "$CSV" "${common[@]}" renderer="$prog" round="$r" load="$(loadavg)" "${kv[@]}"
        done
        a=$(json_get "$WORK/csg.json" hits) b=$(json_get "$WORK/embree.json" hits)
        python3 -c 'import sys; a, b, n = map(int, sys.argv[1:]); sys.exit(abs(a - b) * 10000 > n)' \
            "$a" "$b" "$((SIZE * SIZE))" || die "hit counts disagree: csgtrace $a, Embree $b"
    done
done
echo "  vs_embree: $CSV"
python3 "$ROOT/bench/speed_report.py" "$OUT" --embree
