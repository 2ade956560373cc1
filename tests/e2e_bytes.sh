#!/usr/bin/env bash
# e2e_bytes.sh — results in the output's precision (comm/pixels.h): to an
# 8-bit file (PNG) the workers send the file's bytes, 3 a pixel, instead of
# RGB floats, 12; the file must not change by a byte.
#   - on every example scene and a random one, 61x37, tile 7: homo and
#     hetero PNGs (2 and 3 ranks) are byte-identical (cmp) to the serial
#     PNG, written from the floats themselves, and to the PNG an EXR render's
#     floats give (csgtrace's writer, through a serial render's image);
#   - the stats say which format was used (result_pixels: rgb8 to PNG,
#     float to EXR, none serially) and are truthful: a homo render receives
#     exactly 9 bytes a pixel fewer to PNG than to EXR (tile 8, --batch 4
#     too);
#   - rank 0's store threads (host/store.h): one stores the 8-bit results
#     of every multi-rank PNG render (hetero: unless the fill finished the
#     frame before the OpenCL build), none runs serially or to EXR, and
#     --store-threads 3 gives the same PNG with 3 (store_threads,
#     store_cpu_s in the stats).
#   - compressed results (--compress, comm/pixels_z.h): homo and hetero, with
#     batches and under a relay, give the serial PNG byte for byte, the
#     stats say rgb8z and the master received fewer bytes than with plain
#     bytes; auto compresses only when the ranks span more than one node
#     and the link between them, measured at start, is slow (nodes of two
#     ranks and the link's speed pretended: CSGTRACE_TEST_NODE_RANKS,
#     CSGTRACE_TEST_LINK_MBPS); hetero's records likewise (--hit-records
#     auto: none sent across a slow link).
# Usage: tests/e2e_bytes.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

mpi_sandbox
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$PWD/build/pocl-cache}
MPI=(timeout -s KILL 120 mpirun --bind-to none --oversubscribe)
SZ=(--width 61 --height 37 --tile 7)
"$BIN" gen spheres --count 40 --occupancy 0.4 --seed 7 --width 61 --height 37 \
    --materials opaque,reflective,transparent -o "$T/random.pov" >/dev/null || ko "gen"

for scene in scenes/*.pov "$T/random.pov"; do
    name=$(basename "$scene" .pov)
    "$BIN" render "$scene" "${SZ[@]}" -o "$T/$name-serial.png" --stats "$T/$name-serial.json" \
        >/dev/null 2>&1 || { ko "$name: serial render"; continue; }
    bad=""
    for np in 2 3; do
        for mode in homo hetero; do
            out=$T/$name-$mode-$np.png
            "${MPI[@]}" -np $np "$BIN" render "$scene" "${SZ[@]}" --mode $mode -o "$out" \
                --stats "$out.json" >/dev/null 2>&1 || { bad+=" $mode/$np:failed"; continue; }
            cmp -s "$T/$name-serial.png" "$out" || bad+=" $mode/$np:differs"
            json "$out.json" "j['result_pixels'] == 'rgb8'" || bad+=" $mode/$np:not-rgb8"
            # (hetero with the fill starts the thread once the OpenCL
            # program is built: these tiny frames may be done before)
            json "$out.json" "j['store_threads'] == 1 or '$mode' == 'hetero' and j['tiles_filled'] > 0 and j['store_threads'] == 0" ||
                bad+=" $mode/$np:store-threads"
        done
    done
    json "$T/$name-serial.json" "j['result_pixels'] == 'none'" || bad+=" serial:result_pixels"
    json "$T/$name-serial.json" "j['store_threads'] == 0 and j['store_cpu_s'] == 0" ||
        bad+=" serial:store-threads"
    [ -z "$bad" ] && ok "$name: homo and hetero PNGs (2, 3 ranks, 8-bit results) = the serial PNG, byte for byte" ||
        ko "$name:$bad"
done

# The PNG of an EXR render's floats (the old path: floats to the master,
# converted by the writer) against the 8-bit results' PNG.
"${MPI[@]}" -np 3 "$BIN" render scenes/showcase.pov "${SZ[@]}" --mode homo -o "$T/show.exr" \
    >/dev/null 2>&1 || ko "showcase to EXR"
# A render that writes the EXR's floats to PNG: serial (the master's own
# floats) is that path; the homo EXR equals it (float results).
"$BIN" render scenes/showcase.pov "${SZ[@]}" -o "$T/show-serial.exr" >/dev/null 2>&1
same "$T/show.exr" "$T/show-serial.exr" && cmp -s "$T/showcase-serial.png" "$T/showcase-homo-3.png" &&
    ok "showcase: EXR (float results) = serial EXR, and the 8-bit results' PNG = the PNG of those floats" ||
    ko "showcase: EXR or PNG differs"

# Several store threads: the parts spread over their rings, the same PNG.
# (hetero without the fill: the threads start before the first tile)
for mode in homo hetero; do
    "${MPI[@]}" -np 3 "$BIN" render "$T/random.pov" "${SZ[@]}" --mode $mode --store-threads 3 \
        --fill off -o "$T/st3-$mode.png" --stats "$T/st3-$mode.json" >/dev/null 2>&1 &&
        cmp -s "$T/random-serial.png" "$T/st3-$mode.png" &&
        json "$T/st3-$mode.json" "j['store_threads'] == 3 and j['store_cpu_s'] > 0" &&
        ok "$mode: --store-threads 3: the same PNG, 3 threads in the stats" ||
        ko "$mode: --store-threads 3"
done
"${MPI[@]}" -np 3 "$BIN" render "$T/random.pov" "${SZ[@]}" --mode homo --store-threads 2 \
    -o "$T/st-exr.exr" --stats "$T/st-exr.json" >/dev/null 2>&1 &&
    json "$T/st-exr.json" "j['store_threads'] == 0" &&
    ok "to EXR (float results): no store thread runs" || ko "store threads to EXR"

# An 8-bit format of OpenImageIO's (TIFF): the workers' bytes, handed to
# it as bytes, give the serial PNG's pixels (every 8-bit file is encoded
# one way: comm/pixels.h).
for mode in homo hetero; do
    "${MPI[@]}" -np 3 "$BIN" render "$T/random.pov" "${SZ[@]}" --batch 3 --mode $mode \
        -o "$T/tif-$mode.tif" --stats "$T/tif-$mode.json" >/dev/null 2>&1 &&
        same "$T/random-serial.png" "$T/tif-$mode.tif" &&
        json "$T/tif-$mode.json" "j['result_pixels'] == 'rgb8'" &&
        ok "$mode: to TIFF (8-bit, through OpenImageIO): the serial PNG's pixels" ||
        ko "$mode: to TIFF"
done

# Deflated results: the same PNG, fewer bytes received.
# (tile 1: a part of one pixel compresses to more than its floats would take)
for run in "homo 3" "hetero 3" "homo 3 --batch 4" "hetero 3 --batch 4" "homo 5 --relays 1 --batch 3" \
    "hetero 5 --relays 1" "homo 3 --tile 1 --batch 32"; do
    set -- $run
    mode=$1 np=$2 name=z-$(echo "$run" | tr -d ' -'); shift 2
    bad=""
    for c in on off; do
        "${MPI[@]}" -np $np "$BIN" render "$T/random.pov" "${SZ[@]}" --mode $mode "$@" --compress $c \
            -o "$T/$name-$c.png" --stats "$T/$name-$c.json" >/dev/null 2>&1 || bad+=" $c:failed"
        cmp -s "$T/random-serial.png" "$T/$name-$c.png" || bad+=" $c:differs"
    done
    json "$T/$name-on.json" "j['result_pixels'] == 'rgb8z'" || bad+=" on:not-rgb8z"
    json "$T/$name-off.json" "j['result_pixels'] == 'rgb8'" || bad+=" off:not-rgb8"
    # (fewer bytes but for parts of one pixel, whose frame is larger)
    [[ "$run" == *"--tile 1 "* ]] ||
        python3 -c "import json,sys; a,b=(json.load(open(f))['bytes_received'] for f in sys.argv[1:]); sys.exit(0 if a < b else 1)" \
            "$T/$name-on.json" "$T/$name-off.json" || bad+=" bytes:not-fewer"
    [ -z "$bad" ] && ok "--compress on ($run): the serial PNG, byte for byte; rgb8z, fewer bytes received (but tile 1)" ||
        ko "--compress on ($run):$bad"
done
# auto: plain bytes on one node, and across (pretended) nodes whose link,
# measured at start, is fast (shared memory here); compressed across nodes
# behind a slow one (125 MB/s, gigabit Ethernet, pretended).
TBIN=$BIN-test
if [ -x "$TBIN" ]; then
    for case in "0 0" "2 0" "2 125"; do
        set -- $case
        CSGTRACE_TEST_NODE_RANKS=$1 CSGTRACE_TEST_LINK_MBPS=$2 "${MPI[@]}" -np 3 "$TBIN" render \
            "$T/random.pov" "${SZ[@]}" --mode homo -o "$T/auto-$1-$2.png" --stats "$T/auto-$1-$2.json" \
            >/dev/null 2>&1
    done
    cmp -s "$T/random-serial.png" "$T/auto-0-0.png" && cmp -s "$T/random-serial.png" "$T/auto-2-0.png" &&
        cmp -s "$T/random-serial.png" "$T/auto-2-125.png" &&
        json "$T/auto-0-0.json" "j['result_pixels'] == 'rgb8' and j['link_mbps'] == 0" &&
        json "$T/auto-2-0.json" "j['result_pixels'] == 'rgb8' and j['link_mbps'] > 300" &&
        json "$T/auto-2-125.json" "j['result_pixels'] == 'rgb8z' and j['link_mbps'] == 125" &&
        ok "--compress auto: rgb8 on one node and across a fast link (measured), rgb8z across a slow one; the serial PNG each time" ||
        ko "--compress auto"
    # --hit-records auto: hetero sends its records but across a slow link
    # (not with --simd shadows, whose answers need them)
    for case in "0 0" "2 0" "2 125" "2 125 --simd shadows"; do
        set -- $case
        CSGTRACE_TEST_NODE_RANKS=$1 CSGTRACE_TEST_LINK_MBPS=$2 "${MPI[@]}" -np 3 "$TBIN" render \
            "$T/random.pov" "${SZ[@]}" --mode hetero --fill off "${@:3}" -o "$T/rec-$1-$2-$#.png" \
            --stats "$T/rec-$1-$2-$#.json" >/dev/null 2>&1
    done
    cmp -s "$T/random-serial.png" "$T/rec-0-0-2.png" && cmp -s "$T/random-serial.png" "$T/rec-2-125-2.png" &&
        cmp -s "$T/random-serial.png" "$T/rec-2-125-4.png" &&
        json "$T/rec-0-0-2.json" "j['hit_records'] == 'send'" &&
        json "$T/rec-2-0-2.json" "j['hit_records'] == 'send'" &&
        json "$T/rec-2-125-2.json" "j['hit_records'] == 'retrace' and j['result_pixels'] == 'rgb8z'" &&
        json "$T/rec-2-125-4.json" "j['hit_records'] == 'send'" &&
        ok "--hit-records auto: records sent on one node and across a fast link, none across a slow one (but with --simd shadows); the serial PNG" ||
        ko "--hit-records auto"
else
    ko "--compress auto: $TBIN is not built (make all)"
fi

# Truthful stats: 9 bytes a pixel fewer received to PNG than to EXR.
for extra in "" "--tile 8 --batch 4"; do
    for ext in png exr; do
        "${MPI[@]}" -np 3 "$BIN" render "$T/random.pov" --width 61 --height 37 $extra --mode homo \
            -o "$T/b.$ext" --stats "$T/b-$ext.json" >/dev/null 2>&1 || ko "homo to $ext ($extra)"
    done
    python3 - "$T/b-png.json" "$T/b-exr.json" <<'PY' && ok "bytes_received: EXR - PNG = 9 bytes x 61x37 pixels${extra:+ ($extra)}; result_pixels rgb8 / float" || ko "bytes_received or result_pixels wrong${extra:+ ($extra)}"
import json, sys
p, e = (json.load(open(f)) for f in sys.argv[1:])
ok = (e['bytes_received'] - p['bytes_received'] == 9 * 61 * 37 and
      p['result_pixels'] == 'rgb8' and e['result_pixels'] == 'float')
print(p['bytes_received'], e['bytes_received'])
sys.exit(0 if ok else 1)
PY
done

e2e_finish
