#!/usr/bin/env bash
# demo.sh — what `make demo` runs: the showcase rendered by the homogeneous
# baseline (master/worker over every tile) and by the heterogeneous renderer
# (OpenCL primary pass, then master/worker over the non-empty tiles only),
# each on 3 MPI ranks, then a short comparison of the two runs.
#
# Usage: scenes/demo.sh [SCENE.pov]       (default: scenes/showcase.pov)
# Environment: CSGTRACE (build/csgtrace), RANKS (3), WIDTH x HEIGHT
#   (640 x 480), OUT (out/), MPIRUN (mpirun).
# Writes OUT/NAME_homo.png, OUT/NAME_hetero.png and their stats JSONs.
# Exit status: 0 both renders done (the comparison only reports), 1 otherwise.
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CSGTRACE=${CSGTRACE:-$ROOT/build/csgtrace}
RANKS=${RANKS:-3}
WIDTH=${WIDTH:-640}
HEIGHT=${HEIGHT:-480}
OUT=${OUT:-$ROOT/out}
MPIRUN=${MPIRUN:-mpirun}
SCENE=${1:-$ROOT/scenes/showcase.pov}
NAME=$(basename "$SCENE" .pov)

if [ ! -x "$CSGTRACE" ]; then
    echo "demo: $CSGTRACE is not built (make build/csgtrace)" >&2
    exit 1
fi
if ! command -v "$MPIRUN" >/dev/null 2>&1; then
    echo "demo: $MPIRUN not found (make deps installs openmpi-bin)" >&2
    exit 1
fi

# Open MPI refuses root unless told; ob1 starts faster than probing for UCX;
# PoCL keeps its compiled kernels here instead of under $HOME.
if [ "$(id -u)" = 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
export OMPI_MCA_pml=${OMPI_MCA_pml:-ob1}
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$ROOT/build/pocl-cache}
mkdir -p "$OUT" "$POCL_CACHE_DIR"

render() { # MODE
    local mode=$1
    echo "demo: $NAME, $mode mode, $RANKS ranks, ${WIDTH}x${HEIGHT}"
    "$MPIRUN" -np "$RANKS" --oversubscribe --bind-to none \
        "$CSGTRACE" render "$SCENE" -o "$OUT/${NAME}_$mode.png" --mode "$mode" \
        --width "$WIDTH" --height "$HEIGHT" --stats "$OUT/${NAME}_$mode.json"
}

render homo
render hetero

echo
python3 - "$OUT/${NAME}_homo.json" "$OUT/${NAME}_hetero.json" <<'EOF'
import json, sys

runs = []
for path in sys.argv[1:]:
    try:
        with open(path) as f:
            runs.append(json.load(f))
    except (OSError, ValueError) as e:
        print(f"demo: cannot read {path}: {e}")
        sys.exit(0)

def cell(run, key):
    v = run
    for part in key.split("."):
        v = v.get(part) if isinstance(v, dict) else None
    if v is None:
        return "-"
    return f"{v:.3f}" if isinstance(v, float) else str(v)

rows = [("wall time (s)", "wall_s"), ("primary pass (s)", "primary_s"),
        ("secondary (s)", "secondary_s"), ("kernel compile (s)", "compile_s"),
        ("tiles total", "tiles_total"), ("tiles sent", "tiles_sent"),
        ("tiles degenerate", "tiles_degenerate"), ("occupancy", "occupancy"),
        ("primary rays", "rays.primary"), ("shadow rays", "rays.shadow"),
        ("reflected rays", "rays.reflected"), ("refracted rays", "rays.refracted")]
print(f"{'':20} {'homo':>14} {'hetero':>14}")
for label, key in rows:
    print(f"{label:20} {cell(runs[0], key):>14} {cell(runs[1], key):>14}")
h, t = runs[0].get("wall_s"), runs[1].get("wall_s")
if isinstance(h, (int, float)) and isinstance(t, (int, float)) and t > 0:
    print(f"{'speed-up':20} {'':>14} {h / t:>13.2f}x")
EOF

a=$OUT/${NAME}_homo.png
b=$OUT/${NAME}_hetero.png
if command -v idiff >/dev/null 2>&1; then
    if idiff -fail 0 -failpercent 0 -warn 0 "$a" "$b" >/dev/null 2>&1; then same=yes; else same=no; fi
else
    if cmp -s "$a" "$b"; then same=yes; else same=no; fi
fi
echo "identical pixels:    $same"
echo
echo "images: $a"
echo "        $b"
echo "stats:  $OUT/${NAME}_homo.json"
echo "        $OUT/${NAME}_hetero.json"
