#!/usr/bin/env bash
# bench/vs_povray.sh — csgtrace against POV-Ray 3.7, one core, trace to trace.
#
#   bench/vs_povray.sh [SCENE.pov ...]
#
# Scenes: the arguments, else the paper's six random-sphere scenes
# (`csgtrace gen spheres --count N --occupancy F --seed 1`, N = 10 and 50,
# F = 0.2, 0.5, 0.8, framed at 384 x 384), each rendered at every size of
# SIZES (default "384 1536", square) with the scene's own max_trace_level 5.
# For every scene and size, ROUNDS (default 7) interleaved rounds; a round
# runs both programs once, POV-Ray first in odd rounds and csgtrace first in
# even ones (no program always gets the warmer cache), after one untimed
# run of each:
#   povray +W +H -D -A +WT1 +FN     one render thread, no anti-aliasing;
#       time: its own "Trace Time" (statistics on stderr: it has no
#       machine-readable output); rays: "Rays" (primary, reflected,
#       refracted, transmitted) + "Shadow Ray Tests";
#   csgtrace render --mode serial --stats   one process, one core;
#       time: primary_s + secondary_s (the tile phase: tracing and shading;
#       parsing, flattening with the BVH build, and writing the image are
#       outside, as POV-Ray's parse, bounding and output are outside its
#       trace time); rays: rays.total of the stats.
# Every number read from another program's output is checked against a
# strict pattern before it is used, and is only ever handed on as data
# (key=value arguments of collect.py): nothing from a scene file, a file
# name or an output is ever evaluated as code.
#
# Rows (one a run) go to $BENCH_OUT/vs_povray.csv (started afresh), then
# bench/speed_report.py prints the medians, spreads and ratios, computed
# within this run (the speed-up of a round is POV-Ray's time over
# csgtrace's in that same round).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${CSGTRACE:-$ROOT/build/csgtrace}
ROUNDS=${ROUNDS:-${REPEATS:-7}}
SIZES=${SIZES:-${SIZE:-384 1536}}
SUITE=${SUITE:-standalone}
OUT=${BENCH_OUT:-$ROOT/bench/results}
WORK=${BENCH_WORK:-$ROOT/build/bench}/povray
COLLECT=(python3 "$ROOT/bench/collect.py")
CSV="$OUT/vs_povray.csv"

# The 1-minute load average: this machine is shared, and the tables say how busy it was.
loadavg() { cut -d' ' -f1 /proc/loadavg; }
die() { echo "bench/vs_povray.sh: $*" >&2; exit 1; }
command -v povray >/dev/null || die "povray not found (Debian package povray: make deps)"
[ -x "$BIN" ] || die "$BIN not found: run 'make build/csgtrace' first"
[[ "$ROUNDS" =~ ^[1-9][0-9]{0,2}$ ]] || die "ROUNDS must be a number from 1 to 999"
for s in $SIZES; do [[ "$s" =~ ^[1-9][0-9]{0,4}$ ]] || die "SIZES must hold pixel counts"; done
mkdir -p "$OUT" "$WORK"

# A number as POV-Ray or the stats print it, or the empty string.
number() { [[ "$1" =~ ^[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$ ]] && printf '%s' "$1"; }
# The "(S seconds)" figure of POV-Ray's statistics line $1 (e.g. "Trace Time").
pov_seconds() { number "$(sed -n "s/^ *$1: .*(\([0-9.]*\) seconds).*/\1/p" "$2" | head -1)"; }
# The first count after "$1:" on a statistics line (e.g. "Rays", "Shadow Ray Tests").
pov_count() { number "$(sed -n "s/^$1: *\([0-9]*\).*/\1/p" "$2" | head -1)"; }
# A field of csgtrace's stats JSON, by path (argv, not code).
stat_field() {
    python3 - "$1" "$2" <<'EOF'
import json, sys
v = json.load(open(sys.argv[1]))
for k in sys.argv[2].split("."):
    v = v[k]
print(v)
EOF
}

declare -a SCENES=() NAMES=() COUNTS=() OCCS=()
if [ $# -eq 0 ]; then
    for n in 10 50; do
        for occ in 0.2 0.5 0.8; do
            sc="$WORK/spheres-n$n-o$occ-s1.pov"
            [ -s "$sc" ] || "$BIN" gen spheres --count "$n" --occupancy "$occ" --seed 1 \
                --width 384 --height 384 -o "$sc" >/dev/null || die "gen failed"
            SCENES+=("$sc"); NAMES+=("spheres-n$n-o$occ"); COUNTS+=("$n"); OCCS+=("$occ")
        done
    done
else
    for sc in "$@"; do
        [ -s "$sc" ] || die "no scene $sc"
        SCENES+=("$sc"); NAMES+=("$(basename "$sc" .pov)"); COUNTS+=(""); OCCS+=("")
    done
fi

COMMIT=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
CPU=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1 | tr -s ' ,' ' ')
POV_VERSION=$(povray --version 2>&1 | sed -n 's/^POV-Ray \([0-9.]*\).*/\1/p' | head -1)

povray_run() { # scene size png log
    povray +I"$1" +O"$3" +W"$2" +H"$2" -D -A +WT1 +FN >"$4" 2>&1 \
        || { cat "$4" >&2; die "povray failed on $1"; }
}
csgtrace_run() { # scene size png json log
    "$BIN" render "$1" -o "$3" --mode serial --width "$2" --height "$2" --stats "$4" >"$5" 2>&1 \
        || { cat "$5" >&2; die "csgtrace failed on $1"; }
}

rm -f "$CSV"
for size in $SIZES; do
    for i in "${!SCENES[@]}"; do
        sc=${SCENES[$i]} name=${NAMES[$i]}
        common=(cpu="$CPU" cores="$(nproc)" commit="$COMMIT" suite="$SUITE" povray_version="$POV_VERSION"
                scene="$name" count="${COUNTS[$i]}" occ_target="${OCCS[$i]}" width="$size"
                height="$size")
        echo "== vs_povray $name at ${size}x$size, $ROUNDS rounds"
        povray_run "$sc" "$size" "$WORK/pov.png" "$WORK/pov.log"          # warm-up
        csgtrace_run "$sc" "$size" "$WORK/csg.png" "$WORK/stats.json" "$WORK/csg.log"
        for r in $(seq 1 "$ROUNDS"); do
            order="povray csgtrace"
            [ $((r % 2)) -eq 0 ] && order="csgtrace povray"
            for prog in $order; do
                if [ "$prog" = povray ]; then
                    povray_run "$sc" "$size" "$WORK/pov.png" "$WORK/pov.log"
                    trace=$(pov_seconds "Trace Time" "$WORK/pov.log")
                    rays=$(pov_count "Rays" "$WORK/pov.log")
                    shadow=$(pov_count "Shadow Ray Tests" "$WORK/pov.log")
                    [ -n "$trace" ] && [ -n "$rays" ] && [ -n "$shadow" ] \
                        || die "POV-Ray's statistics lack a time or a ray count ($WORK/pov.log)"
                    "${COLLECT[@]}" append-kv "$CSV" "${common[@]}" renderer=povray round="$r" load="$(loadavg)" \
                        trace_s="$trace" rays="$((rays + shadow))" rays_shadow="$shadow"
                else
                    csgtrace_run "$sc" "$size" "$WORK/csg.png" "$WORK/stats.json" "$WORK/csg.log"
                    p=$(number "$(stat_field "$WORK/stats.json" primary_s)")
                    s=$(number "$(stat_field "$WORK/stats.json" secondary_s)")
                    rays=$(number "$(stat_field "$WORK/stats.json" rays.total)")
                    shadow=$(number "$(stat_field "$WORK/stats.json" rays.shadow)")
                    [ -n "$p" ] && [ -n "$s" ] && [ -n "$rays" ] && [ -n "$shadow" ] \
                        || die "csgtrace's stats lack a time or a ray count ($WORK/stats.json)"
                    "${COLLECT[@]}" append-kv "$CSV" "${common[@]}" renderer=csgtrace round="$r" load="$(loadavg)" \
                        trace_s="$(python3 -c 'import sys; print(float(sys.argv[1]) + float(sys.argv[2]))' "$p" "$s")" \
                        rays="$rays" rays_shadow="$shadow"
                fi
            done
        done
    done
done
echo "  vs_povray: $CSV"
python3 "$ROOT/bench/speed_report.py" "$OUT" --povray
