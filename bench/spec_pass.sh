#!/usr/bin/env bash
# bench/spec_pass.sh — what specialising the OpenCL program on a scene's
# feature set gains (csg/features.h, csg/device/spec.h): the primary pass of
# the general program against programs built for the scene's primitive
# kinds only (+kinds), without interval lists (+csg), and for both (+spec,
# what `csgtrace render` builds; the same program as +kinds+csg).
#
#   bench/spec_pass.sh [--size 1024] [--repeat 7] [--kernels "packet scalar"]
#                      [--parts "kinds csg spec"]
#                      [--out bench/results/spec_pass] SCENE...
#
# SCENE is a .pov file, or spheres:N for `csgtrace gen spheres --count N
# --occupancy 0.5 --seed 1` (cached in build/bench/primary).  Each scene
# goes through build/bench/primary_pass (bench/primary_pass.c): one
# process, the variants interleaved round by round after an untimed round,
# every record compared with the C worker's bit for bit, program builds
# outside every timing.  The C worker runs too (the reference) but is not
# reported here (bench/primary_pass.sh does).  Build times (compile_s: the
# build and PoCL's first launch) come from a POCL_CACHE_DIR made fresh for
# the run: cold the first time a program's options occur in the run (what
# a new feature set costs), a cache load (under 0.1 s) when an earlier
# scene had the same feature set.
# Writes OUT/<scene>.json and OUT/summary.md, and prints the table: per
# scene and variant the median pass (min-max over the rounds) in ms, the
# speed-up over the general program of the same kernel, paired round by
# round (wall clock and process CPU time), and the build time.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
SIZE=1024
REPEAT=7
KERNELS="packet scalar"
PARTS="kinds csg spec"
OUT=$ROOT/bench/results/spec_pass
SCENES=()
while [ $# -gt 0 ]; do
    case "$1" in
    --size) SIZE=${2:?}; shift ;;
    --repeat) REPEAT=${2:?}; shift ;;
    --kernels) KERNELS=${2:?}; shift ;;
    --parts) PARTS=${2:?}; shift ;;
    --out) OUT=${2:?}; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "bench/spec_pass.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    *) SCENES+=("$1") ;;
    esac
    shift
done
[ ${#SCENES[@]} -gt 0 ] || SCENES=(spheres:10 spheres:1000 "$ROOT/scenes/primitives.pov" "$ROOT/scenes/csg_ops.pov")

BIN=$ROOT/build/csgtrace
HARNESS=$ROOT/build/bench/primary_pass
WORK=$ROOT/build/bench/primary
[ -x "$BIN" ] && [ -x "$HARNESS" ] || { echo "build first: make build/csgtrace build/bench/primary_pass" >&2; exit 1; }
mkdir -p "$WORK" "$OUT"
CACHE=$(mktemp -d)
trap 'rm -rf "$CACHE"' EXIT
export POCL_CACHE_DIR=$CACHE
LOAD_START=$(cut -d' ' -f1-3 /proc/loadavg)

VARIANTS=c
for k in $KERNELS; do
    VARIANTS="$VARIANTS,$k"
    for p in $PARTS; do VARIANTS="$VARIANTS,$k+$p"; done
done
NAMES=()
for s in "${SCENES[@]}"; do
    case "$s" in
    spheres:*)
        n=${s#spheres:}
        scene=$WORK/spheres_${n}_occ0.5_seed1.pov
        [ -s "$scene" ] || "$BIN" gen spheres --count "$n" --occupancy 0.5 --seed 1 \
            --width 256 --height 256 -o "$scene" >/dev/null
        name=spheres_$n ;;
    *) scene=$s; name=$(basename "$s" .pov) ;;
    esac
    NAMES+=("$name")
    echo "$name: $SIZE x $SIZE, $REPEAT rounds ($("$BIN" check "$scene" | grep '^specialised:'))" >&2
    "$HARNESS" "$scene" --width "$SIZE" --height "$SIZE" --repeat "$REPEAT" \
        --variants "$VARIANTS" >"$OUT/$name.json"
    "$BIN" check "$scene" | grep '^specialised:' >"$OUT/$name.features"
done
LOAD_END=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$OUT" "$(nproc)" "$LOAD_START" "$LOAD_END" "${NAMES[@]}" <<'PY' | tee "$OUT/summary.md"
import json, os, sys
out, cpus, load0, load1, names = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
def med(x):
    x = sorted(x); n = len(x)
    return x[n // 2] if n % 2 else 0.5 * (x[n // 2 - 1] + x[n // 2])
def paired(base, this):
    r = [b / t for b, t in zip(base, this)]
    return "%.2fx (%.2f-%.2f)" % (med(r), min(r), max(r))
j0 = json.load(open(os.path.join(out, names[0] + ".json")))
print("Primary pass, general against specialised OpenCL programs, %d x %d, %s, %d interleaved "
      "rounds; device: %s." % (j0["width"], j0["height"], j0["precision"], j0["repeat"], j0["device"]))
print("Machine: %s CPUs, load average %s at the start, %s at the end.\n" % (cpus, load0, load1))
print("Speed-up: the general program's time over this variant's, round by round (the same round "
      "ran both), median (min-max); wall clock and CPU time of the process.\n")
print("| scene | variant | pass ms: median (min-max) | speed-up, wall | speed-up, CPU | build s | identical |")
print("| --- | --- | ---: | ---: | ---: | ---: | :---: |")
for name in names:
    j = json.load(open(os.path.join(out, name + ".json")))
    feat = open(os.path.join(out, name + ".features")).read().strip().replace("specialised: ", "")
    v = j["variants"]
    for k, r in v.items():
        if k == "c":
            continue
        base = v[k.split("+")[0]]
        label = "%s (%s)" % (name, feat) if k in ("packet", "scalar") and k == list(v)[1] else name
        print("| %s | %s | %.2f (%.2f-%.2f) | %s | %s | %.2f | %s |" % (
            label, k, r["median_s"] * 1e3, r["min_s"] * 1e3, r["max_s"] * 1e3,
            paired(base["rounds_s"], r["rounds_s"]), paired(base["cpu_rounds_s"], r["cpu_rounds_s"]),
            r["compile_s"], "yes" if r["identical"] else "NO"))
PY
