#!/usr/bin/env bash
# bench/vs_povray.sh — csgtrace against POV-Ray 3.7 on the same scenes.
#
#   bench/vs_povray.sh [SCENE.pov ...]     (default: one generated scene, 30 spheres, 50 %)
#
# Each scene is rendered R times (REPEATS, default 3) by
#   povray +W$SIZE +H$SIZE -D -A +WT2          (2 threads, no anti-aliasing, default
#                                                File_Gamma; the trace depth is the scene's
#                                                own `max_trace_level 5`: POV-Ray 3.7 has no
#                                                command-line switch for it)
#   csgtrace render --mode homo under mpirun -np $RANKS (1 master + 2 workers)
#   csgtrace render --mode serial (one process)
# at the same size and depth.  Times: POV-Ray's own parse + bounding + trace
# time (from its statistics on stderr: it has no machine-readable output) and
# csgtrace's time_s = wall_s - compile_s from --stats JSON; the process wall
# times (start-up included) are recorded too, as ext_s.  Image agreement: idiff
# of each csgtrace image against the POV-Ray image (mean error, PSNR, % of
# pixels over 0.05).  Rows go to $BENCH_OUT/vs_povray.csv (started afresh);
# bench/run.sh --report puts the table (medians, time ratio csgtrace/POV-Ray)
# into RESULTS.md.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${CSGTRACE:-$ROOT/build/csgtrace}
RANKS=${RANKS:-3}
REPEATS=${REPEATS:-3}
SIZE=${SIZE:-384}
SUITE=${SUITE:-standalone}
OUT=${BENCH_OUT:-$ROOT/bench/results}
WORK=${BENCH_WORK:-$ROOT/build/bench}/povray
COLLECT="python3 $ROOT/bench/collect.py"
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
CSV="$OUT/vs_povray.csv"

die() { echo "bench/vs_povray.sh: $*" >&2; exit 1; }
command -v povray >/dev/null || die "povray not found (Debian package povray)"
command -v idiff >/dev/null || die "idiff not found (Debian package openimageio-tools)"
[ -x "$BIN" ] || die "$BIN not found: run 'make build/csgtrace' first"
mkdir -p "$OUT" "$WORK"

if [ $# -eq 0 ]; then
    def="$WORK/spheres-n30-o50-s1.pov"
    [ -s "$def" ] || "$BIN" gen spheres --count 30 --occupancy 0.5 --seed 1 \
        --width "$SIZE" --height "$SIZE" -o "$def" >/dev/null
    set -- "$def"
fi

COMMIT=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
CPU=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1 | tr -s ' ,' ' ')
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN{printf "%.6f", b - a}'; }

# The "(S seconds)" figure of one of POV-Ray's statistics lines, e.g. "Trace Time".
pov_seconds() { sed -n "s/.*$1:.*(\([0-9.]*\) seconds).*/\1/p" "$2" | head -1; }

# Scene parameters from gen's header comment (empty for other scenes).
param() { sed -n "1s/.*--$1 \([^ ]*\).*/\1/p" "$2"; }

rm -f "$CSV"
for sc in "$@"; do
    [ -s "$sc" ] || die "no scene $sc"
    name=$(basename "$sc" .pov)
    count=$(param count "$sc"); occ=$(param occupancy "$sc")
    occ=${occ:+$(awk -v o="$occ" 'BEGIN{print o*100}')}
    common=(cpu="$CPU" cores="$(nproc)" commit="$COMMIT" suite="$SUITE" scene="$name" count="$count"
            occ_target="$occ" width="$SIZE" height="$SIZE" ranks="$RANKS")
    pov_png="$WORK/$name-povray.png"
    echo "== vs_povray $name at ${SIZE}x$SIZE"
    # Warm-up of both programs (file cache, PoCL cache): not recorded.
    povray +I"$sc" +O"$pov_png" +W"$SIZE" +H"$SIZE" -D -A +WT2 +FN >"$WORK/pov.log" 2>&1 \
        || { cat "$WORK/pov.log" >&2; die "povray failed on $sc"; }
    "$BIN" render "$sc" -o "$WORK/$name-serial.png" --mode serial --width "$SIZE" \
        --height "$SIZE" >/dev/null 2>&1 || die "csgtrace serial failed on $sc"
    for r in $(seq 1 "$REPEATS"); do
        t0=$(now)
        povray +I"$sc" +O"$pov_png" +W"$SIZE" +H"$SIZE" -D -A +WT2 +FN >"$WORK/pov.log" 2>&1 \
            || { cat "$WORK/pov.log" >&2; die "povray failed on $sc"; }
        ext=$(since "$t0")
        parse=$(pov_seconds "Parse Time" "$WORK/pov.log")
        bound=$(pov_seconds "Bounding Time" "$WORK/pov.log")
        trace=$(pov_seconds "Trace Time" "$WORK/pov.log")
        [ -n "$trace" ] || die "no Trace Time in POV-Ray's statistics ($WORK/pov.log)"
        total=$(awk -v p="${parse:-0}" -v b="${bound:-0}" -v t="$trace" 'BEGIN{printf "%.6f", p + b + t}')
        $COLLECT append-kv "$CSV" "${common[@]}" renderer=povray repeat="$r" \
            date="$(date -u +%Y-%m-%dT%H:%M:%SZ)" time_s="$total" ext_s="$ext" \
            pov_parse_s="$parse" pov_bounding_s="$bound" pov_trace_s="$trace"
        for mode in homo serial; do
            img="$WORK/$name-$mode.png"
            json="$WORK/stats.json"
            cmd=("$BIN" render "$sc" -o "$img" --mode "$mode" --width "$SIZE" --height "$SIZE"
                 --stats "$json")
            [ "$mode" = serial ] || cmd=(mpirun -np "$RANKS" --oversubscribe --bind-to none "${cmd[@]}")
            t0=$(now)
            "${cmd[@]}" >"$WORK/log.txt" 2>&1 || { cat "$WORK/log.txt" >&2; die "failed: ${cmd[*]}"; }
            ext=$(since "$t0")
            idiff -fail 0.05 -warn 0.05 "$pov_png" "$img" >"$WORK/idiff.txt" 2>&1 || true
            # shellcheck disable=SC2046  # key=value words
            $COLLECT append "$CSV" "$json" "${common[@]}" renderer="$mode" repeat="$r" \
                date="$(date -u +%Y-%m-%dT%H:%M:%SZ)" ext_s="$ext" \
                $($COLLECT idiff "$WORK/idiff.txt")
        done
    done
done
echo "  vs_povray: $CSV"
