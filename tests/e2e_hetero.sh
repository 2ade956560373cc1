#!/usr/bin/env bash
# e2e_hetero.sh — the heterogeneous mode and the comparison, end to end:
# hetero == homo == serial bit for bit on generated random scenes (hetero
# with both OpenCL kernel variants, --cl-kernel scalar and packet), the
# degenerate-tile bookkeeping at its extremes (no object: every tile
# skipped; a screen-filling object: none), a 1x1 image, `compare` (table,
# identical images, JSON), and the generator's occupancy target on a sample
# of the benchmark grid; the program specialised on each example scene
# against the general one; the fill (workers render whole tiles while the
# OpenCL program builds) with a delayed build: every tile filled, or a
# fixed number and the pass the rest; --pass auto without an OpenCL
# platform renders with a warning; --simd shadows (the pass answers the
# primary hits' shadow rays) gives the same images.
# Every hetero render here runs --fill off unless it says otherwise: with
# the fill on, a small image may be rendered before the pass has begun,
# and the comparisons of the pass's records would prove nothing.
set -u
source "$(dirname "$0")/lib_e2e.sh"
BIN=$HOOKED_BIN # (CSGTRACE_TEST_* hooks)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(pwd)/build/pocl-cache}
MPIRUN=(mpirun --oversubscribe --bind-to none)

render() { # render NAME RANKS MODE SCENE EXTRA... -> $T/NAME.pfm, $T/NAME.json
    local name=$1 ranks=$2 mode=$3 scene=$4
    shift 4
    [ "$mode" = hetero ] && [[ " $* " != *" --fill "* ]] && set -- "$@" --fill off
    if [ "$ranks" = 0 ]; then
        "$BIN" render "$scene" -o "$T/$name.pfm" --mode "$mode" --stats "$T/$name.json" "$@" >/dev/null 2>"$T/$name.err"
    else
        "${MPIRUN[@]}" -np "$ranks" "$BIN" render "$scene" -o "$T/$name.pfm" --mode "$mode" \
            --stats "$T/$name.json" "$@" >/dev/null 2>"$T/$name.err"
    fi
}

# --- random scenes: hetero == homo == serial ---
for spec in "5 0.2 1" "20 0.5 2" "40 0.8 3" "200 0.6 4"; do
    set -- $spec
    scene="$T/gen_$3.pov"
    if ! "$BIN" gen spheres --count "$1" --occupancy "$2" --seed "$3" --width 96 --height 72 -o "$scene" >/dev/null; then
        ko "gen spheres $spec"
        continue
    fi
    render s_$3 0 serial "$scene" --width 96 --height 72 --tile 16
    render h_$3 3 homo "$scene" --width 96 --height 72 --tile 16
    render x_$3 3 hetero "$scene" --width 96 --height 72 --tile 16 --cl-kernel packet
    render xs_$3 3 hetero "$scene" --width 96 --height 72 --tile 16 --cl-kernel scalar
    if same "$T/s_$3.pfm" "$T/h_$3.pfm" && same "$T/s_$3.pfm" "$T/x_$3.pfm" &&
        same "$T/s_$3.pfm" "$T/xs_$3.pfm"; then
        ok "random scene ($1 spheres, occupancy $2): hetero (packet and scalar kernels) == homo == serial"
    else
        ko "random scene ($1 spheres, occupancy $2): images differ"
    fi
    if json "$T/x_$3.json" "j['tiles_sent'] + j['tiles_degenerate'] == j['tiles_total'] and j['tiles_sent'] <= j['tiles_total']"; then
        ok "random scene $3: tiles sent + skipped = total"
    else
        ko "random scene $3: tile bookkeeping"
    fi
done

# --- --hit-records retrace: the pass only tells which tiles have hits; the
# workers trace those tiles' primary rays themselves (a slow link): the
# serial image, the same hits, the same tiles skipped, no records sent
# (a few bytes a tile where the records took 8 a pixel); --simd shadows
# with it is refused (exit 2, one message) ---
scene=$T/gen_2.pov
render rt_send 3 hetero "$scene" --width 96 --height 72 --tile 16 --batch 2
render rt_re 3 hetero "$scene" --width 96 --height 72 --tile 16 --batch 2 --hit-records retrace
render rt_rel 4 hetero "$scene" --width 96 --height 72 --tile 8 --relays 1 --hit-records retrace \
    --precision double
render rt_sd 0 serial "$scene" --width 96 --height 72 --precision double
if same "$T/s_2.pfm" "$T/rt_re.pfm" && same "$T/s_2.pfm" "$T/rt_send.pfm" &&
    same "$T/rt_sd.pfm" "$T/rt_rel.pfm" &&
    python3 - "$T/rt_send.json" "$T/rt_re.json" "$T/rt_rel.json" <<'PY'; then
import json, sys
a, b, c = (json.load(open(f)) for f in sys.argv[1:])
pixels = a['width'] * a['height']
ok = (a['hit_records'] == 'send' and b['hit_records'] == 'retrace' and
      c['hit_records'] == 'retrace' and a['tiles_degenerate'] > 0 and
      b['tiles_degenerate'] == a['tiles_degenerate'] and b['pixels_hit'] == a['pixels_hit'] and
      a['bytes_sent'] - b['bytes_sent'] >= 8 * pixels // 2 and
      b['bytes_sent'] < a['bytes_sent'] // 10)
print(a['bytes_sent'], b['bytes_sent'], a['pixels_hit'], b['pixels_hit'])
sys.exit(0 if ok else 1)
PY
    ok "--hit-records retrace (batches, a relay, double): the serial image, the same hits and skipped tiles, no records sent"
else
    ko "--hit-records retrace: images or stats differ"
fi
"$BIN" render "$scene" -o "$T/rt_bad.pfm" --mode hetero --hit-records retrace --simd shadows \
    >/dev/null 2>"$T/rt_bad.err"
rc=$?
[ $rc = 2 ] && [ "$(grep -c 'error:' "$T/rt_bad.err")" = 1 ] && [ ! -e "$T/rt_bad.pfm" ] &&
    ok "--hit-records retrace with --simd shadows: exit 2, one message" ||
    ko "--hit-records retrace with --simd shadows: exit $rc"

# --- --simd shadows: the pass answers the primary hits' shadow rays (a
# transparent blocker, a spotlight, an area light, a shadowless light and
# 36 lights: the unknown paths too); hetero --simd shadows == serial with
# both kernels in both precisions (== homo, == --simd primary in float),
# the answers taken and the rest traced ---
{
    echo 'camera { location <0, 3, -8> look_at <0, 0.5, 0> }'
    echo 'plane { y, 0 pigment { color rgb 1 } finish { reflection 0.2 } }'
    echo 'sphere { <-1.5, 1, 0>, 1 pigment { color rgb <1, 0.2, 0.2> } }'
    echo 'sphere { <1.5, 1, 0>, 1 pigment { color rgbf <0.5, 0.5, 1, 0.8> } }'
    echo 'difference { box { <-0.5, 0, -2.5>, <0.5, 2, -2> } sphere { <0, 1, -2.5>, 0.4 } pigment { color rgb 1 } }'
    echo 'light_source { <-5, 8, -5> color rgb 0.5 }'
    echo 'light_source { <5, 8, -5> color rgb 0.5 spotlight point_at <0, 0, 0> radius 15 falloff 25 }'
    echo 'light_source { <0, 8, -6> color rgb 0.3 area_light <1, 0, 0>, <0, 0, 1>, 2, 2 }'
    echo 'light_source { <-3, 5, 2> color rgb 0.3 shadowless }'
    for i in $(seq 0 31); do echo "light_source { <$((i % 8 - 4)), 6, $((i / 8 - 2))> color rgb 0.02 }"; done
} >"$T/shadow_answers.pov"
for prec in float double; do
    sa=(--width 48 --height 36 --tile 16 --precision $prec)
    render sa_s_$prec 0 serial "$T/shadow_answers.pov" "${sa[@]}"
    all=1
    runs="scalar_shadows packet_shadows"
    if [ $prec = float ]; then
        runs="$runs packet_primary"
        render sa_h_$prec 3 homo "$T/shadow_answers.pov" "${sa[@]}"
        same "$T/sa_s_$prec.pfm" "$T/sa_h_$prec.pfm" || all=0
    fi
    for run in $runs; do
        render sa_x_${prec}_$run 3 hetero "$T/shadow_answers.pov" "${sa[@]}" --cl-kernel ${run%_*} --simd ${run#*_}
        same "$T/sa_s_$prec.pfm" "$T/sa_x_${prec}_$run.pfm" || all=0
        if [ ${run#*_} = shadows ]; then
            json "$T/sa_x_${prec}_$run.json" "j['rays']['shadow_answered'] > 0 and j['rays']['shadow'] > 0" || all=0
        else
            json "$T/sa_x_${prec}_$run.json" "j['rays']['shadow_answered'] == 0" || all=0
        fi
    done
    if [ $all = 1 ]; then
        ok "$prec: hetero --simd shadows ($runs) == serial (float: == homo), answers taken and some traced"
    else
        ko "$prec: --simd shadows: images differ or no answer taken"
    fi
done

# --- the program specialised on each example scene's features (the default)
# gives the general program's image (CSGTRACE_CL_SPECIALISE=0) and serial's ---
for scene in scenes/*.pov; do
    b=$(basename "$scene" .pov)
    render sp_s_$b 0 serial "$scene" --width 64 --height 48 --tile 16
    render sp_x_$b 0 hetero "$scene" --width 64 --height 48 --tile 16
    CSGTRACE_CL_SPECIALISE=0 render sp_g_$b 0 hetero "$scene" --width 64 --height 48 --tile 16
    if same "$T/sp_s_$b.pfm" "$T/sp_x_$b.pfm" && same "$T/sp_s_$b.pfm" "$T/sp_g_$b.pfm"; then
        ok "$b ($("$BIN" check "$scene" | sed -n 's/^specialised: //p')): specialised hetero == general hetero == serial"
    else
        ko "$b: the specialised program's image differs: $(head -c 300 "$T/sp_x_$b.err")"
    fi
done
if json "$T/sp_x_spheres_grid.json" "j['cl_program'] == 'sphere plane; no csg'" &&
    json "$T/sp_g_spheres_grid.json" "j['cl_program'] == 'general'" &&
    json "$T/sp_s_spheres_grid.json" "j['cl_program'] == ''"; then
    ok "the stats name the program: specialised, general, none (serial)"
else
    ko "cl_program in the stats: $(grep cl_program "$T"/sp_*_spheres_grid.json)"
fi
CSGTRACE_CL_SPECIALISE=2 render sp_bad 0 hetero "$T/gen_1.pov" --width 8 --height 8
grep -q "CSGTRACE_CL_SPECIALISE must be 0 or 1" "$T/sp_bad.err" &&
    ok "a bad CSGTRACE_CL_SPECIALISE is refused" || ko "CSGTRACE_CL_SPECIALISE=2: $(head -c 300 "$T/sp_bad.err")"

# --- the pass's slices as large as $CSGTRACE_CL_SLICE asks (a GPU's
# default): 5000 records of 96 a row are 52.1 rows, 64 in tiles of 16: two
# slices for 72 rows where the default takes three (two tile rows a slice);
# the records written in place (PoCL's CPU device works in host memory),
# the serial image; the device's clock tells the pass's kernels and copies
# (a queue that times its commands: PoCL's does), within its span ---
CSGTRACE_CL_SLICE=5000 render sl_2 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16
render sl_d_2 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16
if same "$T/s_2.pfm" "$T/sl_2.pfm" && json "$T/sl_2.json" "j['slices'] == 2" &&
    json "$T/sl_d_2.json" "j['slices'] == 3" && json "$T/sl_2.json" "j['cl_records'] == 'in place'" &&
    json "$T/sl_2.json" "j['pass_kernel_s'] > 0 and j['pass_copy_s'] >= 0 and
        j['pass_device_s'] >= j['pass_kernel_s'] + j['pass_copy_s'] - 1e-9"; then
    ok "CSGTRACE_CL_SLICE=5000: two slices of 64 rows (the default: three), in place, the serial image, the device's times"
else
    ko "CSGTRACE_CL_SLICE: $(grep -h -e '"slices"' -e cl_records -e '"pass_' "$T/sl_2.json" "$T/sl_d_2.json" | tr -d '\n') $(head -c 300 "$T/sl_2.err")"
fi
CSGTRACE_CL_SLICE=0 render sl_bad 0 hetero "$T/gen_1.pov" --width 8 --height 8
grep -q "CSGTRACE_CL_SLICE must be a whole number" "$T/sl_bad.err" &&
    ok "a bad CSGTRACE_CL_SLICE is refused" || ko "CSGTRACE_CL_SLICE=0: $(head -c 300 "$T/sl_bad.err")"

# --- the POV-Ray cross-check scenes (tests/povray: the gamma modes, the
# constructs of POV-Ray's sample scenes): the same image in every mode and
# both kernels (the linear floats, so every file's bytes too), each on the
# general program: compiled once for all the scenes (a specialised build
# of each kernel for each scene cost the suite a PoCL compile a scene and
# kernel; the specialisation is checked on scenes/ above, and these
# scenes' constructs are the shading's, which no program holds) ---
for scene in tests/povray/*.pov; do
    b=$(basename "$scene" .pov)
    render pv_s_$b 0 serial "$scene" --width 64 --height 48 --tile 16
    render pv_h_$b 3 homo "$scene" --width 64 --height 48 --tile 16
    CSGTRACE_CL_SPECIALISE=0 render pv_x_$b 3 hetero "$scene" --width 64 --height 48 --tile 16 \
        --cl-kernel packet
    CSGTRACE_CL_SPECIALISE=0 render pv_xs_$b 0 hetero "$scene" --width 64 --height 48 --tile 16 \
        --cl-kernel scalar
    if same "$T/pv_s_$b.pfm" "$T/pv_h_$b.pfm" && same "$T/pv_s_$b.pfm" "$T/pv_x_$b.pfm" &&
        same "$T/pv_s_$b.pfm" "$T/pv_xs_$b.pfm"; then
        ok "tests/povray/$b: hetero (packet and scalar kernels, the general program) == homo == serial"
    else
        ko "tests/povray/$b: the modes' images differ: $(head -c 300 "$T/pv_x_$b.err")"
    fi
done

# --- supersampling: every sample traced by the OpenCL pass, same pixels ---
for spp in 4 8 3; do
    render ss$spp 0 serial "$T/gen_1.pov" --width 96 --height 72 --spp $spp
    render xs$spp 3 hetero "$T/gen_1.pov" --width 96 --height 72 --spp $spp --tile 16
    render xss$spp 3 hetero "$T/gen_1.pov" --width 96 --height 72 --spp $spp --tile 16 --cl-kernel scalar
    if same "$T/ss$spp.pfm" "$T/xs$spp.pfm" && same "$T/ss$spp.pfm" "$T/xss$spp.pfm" &&
        json "$T/xs$spp.json" "j['spp'] == $spp and j['rays']['primary'] == 96 * 72 * $spp and j['tiles_degenerate'] > 0"; then
        ok "--spp $spp: hetero (both kernels) == serial, $spp primary rays a pixel, degenerate tiles still skipped"
    else
        ko "--spp $spp: hetero differs from serial or wrong counts"
    fi
done

# --- the other knobs: the same image in every mode ---
render kd 0 serial scenes/glass.pov --width 64 --height 48 --depth 2 --threshold 0.05
render kh 3 homo scenes/glass.pov --width 64 --height 48 --depth 2 --threshold 0.05
render kx 3 hetero scenes/glass.pov --width 64 --height 48 --depth 2 --threshold 0.05
render k5 0 serial scenes/glass.pov --width 64 --height 48
if same "$T/kd.pfm" "$T/kh.pfm" && same "$T/kd.pfm" "$T/kx.pfm" && ! same "$T/kd.pfm" "$T/k5.pfm"; then
    ok "--depth 2 --threshold 0.05: serial == homo == hetero (and not the default image)"
else
    ko "--depth/--threshold: modes differ, or the knobs changed nothing"
fi

# --- double precision hetero on a random scene ---
render sd 0 serial "$T/gen_2.pov" --width 96 --height 72 --precision double
render xd 3 hetero "$T/gen_2.pov" --width 96 --height 72 --precision double --cl-kernel packet
render xds 3 hetero "$T/gen_2.pov" --width 96 --height 72 --precision double --cl-kernel scalar
same "$T/sd.pfm" "$T/xd.pfm" && same "$T/sd.pfm" "$T/xds.pfm" && ok "double: hetero (both kernels) == serial" || ko "double: hetero differs from serial"

# --- boxes of zero thickness (sheets, in CSG and under transforms), shaded:
#     the same image in every mode, in both precisions ---
fb=tests/povray/flat_boxes.pov
for prec in float double; do
    render fbs_$prec 0 serial $fb --width 80 --height 60 --precision $prec
    render fbh_$prec 3 homo $fb --width 80 --height 60 --precision $prec
    render fbx_$prec 3 hetero $fb --width 80 --height 60 --precision $prec --cl-kernel packet
    render fbxs_$prec 3 hetero $fb --width 80 --height 60 --precision $prec --cl-kernel scalar
    if same "$T/fbs_$prec.pfm" "$T/fbh_$prec.pfm" && same "$T/fbs_$prec.pfm" "$T/fbx_$prec.pfm" &&
        same "$T/fbs_$prec.pfm" "$T/fbxs_$prec.pfm"; then
        ok "flat boxes ($prec): hetero (both kernels) == homo == serial"
    else
        ko "flat boxes ($prec): images differ"
    fi
done

# --- the kernel variant from the environment; a bad one refused ---
CSGTRACE_CL_KERNEL=scalar "${MPIRUN[@]}" -np 3 "$BIN" render scenes/csg_ops.pov -o "$T/env.pfm" \
    --mode hetero --width 64 --height 48 --fill off >/dev/null 2>&1
render envs 0 serial scenes/csg_ops.pov --width 64 --height 48
same "$T/env.pfm" "$T/envs.pfm" && ok "\$CSGTRACE_CL_KERNEL=scalar: hetero == serial" || ko "\$CSGTRACE_CL_KERNEL=scalar: hetero differs"
if CSGTRACE_CL_KERNEL=wide CSGTRACE_TEST_CL_DELAY_MS=300 "$BIN" render scenes/showcase.pov \
    -o "$T/bad.pfm" --mode hetero --width 8 --height 8 >/dev/null 2>"$T/bad.err"; then
    ko "a bad \$CSGTRACE_CL_KERNEL was accepted"
else
    grep -q "CSGTRACE_CL_KERNEL" "$T/bad.err" && [ ! -e "$T/bad.pfm" ] &&
        ok "a bad \$CSGTRACE_CL_KERNEL is refused with a message (also when the fill rendered every tile first)" ||
        ko "bad CSGTRACE_CL_KERNEL: $(head -c 300 "$T/bad.err")"
fi
"$BIN" render scenes/showcase.pov -o "$T/badk.pfm" --cl-kernel wide >/dev/null 2>"$T/badk.err"
[ $? -eq 2 ] && grep -q "cl-kernel" "$T/badk.err" && ok "--cl-kernel wide: a usage error (exit 2)" || ko "--cl-kernel wide: $(head -c 300 "$T/badk.err")"

# --- --precision auto: float for an ordinary scene, double far from the origin,
#     the same choice in every mode ---
printf 'camera { location <1e6, 1e6, 1e6-5> look_at <1e6, 1e6, 1e6> }\nlight_source { <1e6-3, 1e6+4, 1e6-5> color rgb 1 }\nsphere { <1e6, 1e6, 1e6>, 0.5 pigment { color rgb 1 } }\n' >"$T/far.pov"
render af 0 serial "$T/far.pov" --width 48 --height 36 --precision auto
render ax 3 hetero "$T/far.pov" --width 48 --height 36 --precision auto
render ad 0 serial "$T/far.pov" --width 48 --height 36 --precision double
render an 0 serial scenes/showcase.pov --width 48 --height 36 --precision auto
if json "$T/af.json" "j['precision'] == 'double' and j['precision_auto'].startswith('double')" &&
    json "$T/an.json" "j['precision'] == 'float'" && same "$T/af.pfm" "$T/ax.pfm" && same "$T/af.pfm" "$T/ad.pfm"; then
    ok "--precision auto: double far from the origin (in every mode), float for the showcase"
else
    ko "--precision auto: wrong choice or modes differ"
fi

# --- no object: every tile degenerate, nothing sent ---
printf 'camera { location <0,0,-5> look_at 0 }\nbackground { color rgb <0.1, 0.2, 0.3> }\n' >"$T/empty.pov"
render e 3 hetero "$T/empty.pov" --width 100 --height 70
if json "$T/e.json" "j['tiles_degenerate'] == j['tiles_total'] == 12 and j['tiles_sent'] == 0 and j['occupancy'] == 0"; then
    ok "empty scene: all 12 tiles degenerate, none sent"
else
    ko "empty scene: $(cat "$T/e.json" 2>/dev/null | tr -d '\n' | head -c 300)"
fi
render es 0 serial "$T/empty.pov" --width 100 --height 70
same "$T/e.pfm" "$T/es.pfm" && ok "empty scene: hetero == serial (background)" || ko "empty scene: background differs"

# --- a screen-filling object: no tile degenerate ---
printf 'camera { location <0,0,-5> look_at 0 }\nlight_source { <0, 5, -5> color rgb 1 }\nplane { z, 1 pigment { color rgb 1 } }\n' >"$T/full.pov"
render f 3 hetero "$T/full.pov" --width 100 --height 70
if json "$T/f.json" "j['tiles_degenerate'] == 0 and j['tiles_sent'] == j['tiles_total'] == 12 and j['occupancy'] == 1"; then
    ok "screen-filling scene: no tile degenerate"
else
    ko "screen-filling scene: $(cat "$T/f.json" 2>/dev/null | tr -d '\n' | head -c 300)"
fi

# --- a 1x1 image ---
render o 3 hetero scenes/showcase.pov --width 1 --height 1
render os 0 serial scenes/showcase.pov --width 1 --height 1
same "$T/o.pfm" "$T/os.pfm" && ok "1x1 image: hetero == serial" || ko "1x1 image differs"

# --- compare: the table, identical images, the JSON of both modes ---
if "${MPIRUN[@]}" -np 3 "$BIN" compare scenes/csg_ops.pov --width 96 --height 72 --repeat 2 \
    -o "$T/cmp" --stats "$T/cmp.json" >"$T/cmp.out" 2>"$T/cmp.err"; then
    ok "compare exits 0"
else
    ko "compare failed: $(head -c 300 "$T/cmp.err")"
fi
grep -q "identical, bit for bit" "$T/cmp.out" && ok "compare reports identical images" || ko "compare table: $(head -c 400 "$T/cmp.out")"
# the advantage is reported only when both modes' workers were busy at
# least 90 % of their tile phase (medians), else the line says why: checked
# against the JSON's figures, whichever way this run went, and on a frame
# so small that its workers mostly wait
compare_guard() { # compare_guard OUT JSON -> 0 when the line matches the figures
    python3 - "$1" "$2" <<'PY'
import json, statistics, sys
out, j = open(sys.argv[1]).read(), json.load(open(sys.argv[2]))
busy = {m: statistics.median(r['busy_fraction'] for r in j[m]) for m in ('homo', 'hetero')}
healthy = all(b >= 0.90 for b in busy.values())
line = [l for l in out.splitlines() if l.startswith('advantage')]
if healthy:
    ok = (line and line[0].startswith('advantage (homo - hetero) / homo: ') and
          j['advantage_pct'] is not None)
else:
    ok = (line and line[0].startswith('advantage: not reported: the ') and
          'under 90 %' in line[0] and j['advantage_pct'] is None and
          'busy' in j['advantage_withheld'])
print(busy, line[:1])
sys.exit(0 if ok else 1)
PY
}
compare_guard "$T/cmp.out" "$T/cmp.json" >"$T/guard.log" &&
    ok "compare: the advantage is reported only when every mode's workers were busy >= 90 % ($(cat "$T/guard.log"))" ||
    ko "compare's advantage line against its busy figures: $(cat "$T/guard.log")"
"${MPIRUN[@]}" -np 3 "$BIN" compare scenes/csg_ops.pov --width 16 --height 12 --tile 2 --repeat 1 \
    --stats "$T/cmp2.json" >"$T/cmp2.out" 2>"$T/cmp2.err" &&
    compare_guard "$T/cmp2.out" "$T/cmp2.json" >"$T/guard2.log" &&
    ok "compare on a frame whose workers mostly wait: the same rule ($(cat "$T/guard2.log"))" ||
    ko "compare guard, tiny frame: $(cat "$T/guard2.log") $(head -c 300 "$T/cmp2.err")"
if json "$T/cmp.json" "j['identical'] and len(j['homo']) == 2 and len(j['hetero']) == 2 and j['hetero'][0]['mode'] == 'hetero' and j['hetero'][0]['compile_s'] == 0"; then
    ok "compare JSON: both modes, R runs each, no compilation in timed runs"
else
    ko "compare JSON: $(head -c 300 "$T/cmp.json")"
fi
same "$T/cmp-homo.png" "$T/cmp-hetero.png" && ok "compare -o writes both images" || ko "compare images missing or different"

# --- the program cache (host/pass/cl_cache.h): a render stores the program's
# binary, the next one builds from it with the same image; a damaged or
# foreign file is ignored and replaced; "off" writes nothing; a cache that
# cannot be written changes nothing but the speed ---
cache="$T/clcache"
scene=scenes/showcase.pov
CSGTRACE_CL_CACHE=$cache render cc_1 0 hetero "$scene" --width 64 --height 48 --tile 16
bins=("$cache"/*.clbin)
if [ ${#bins[@]} = 1 ] && [ -s "${bins[0]}" ] && [ "$(stat -c %a "$cache")" = 700 ]; then
    ok "program cache: one binary stored, folder private"
else
    ko "program cache: expected one .clbin in a 0700 folder: $(ls -la "$cache" 2>&1 | head -5)"
fi
CSGTRACE_CL_CACHE=$cache render cc_2 0 hetero "$scene" --width 64 --height 48 --tile 16
same "$T/cc_1.pfm" "$T/cc_2.pfm" && same "$T/cc_1.pfm" "$T/sp_s_showcase.pfm" &&
    ok "program cache: the render built from the cached binary == the first == serial" ||
    ko "program cache: images differ"
bin=${bins[0]}
valid_bin() { # the header's size and SHA-256 of key and payload match (cl_cache.c)
    python3 -c "
import hashlib, struct, sys
b = open(sys.argv[1], 'rb').read()
magic, key, size, digest = struct.unpack('<16s32sQ32s', b[:88])
ok = magic.startswith(b'csgtrace-cl-2') and size == len(b) - 88
sys.exit(0 if ok and hashlib.sha256(key + b[88:]).digest() == digest else 1)" "$1"
}
valid_bin "$bin" && ok "program cache: the stored file's header matches its payload" || ko "program cache: stored file invalid"
printf 'XXXXXXXX' | dd of="$bin" bs=1 seek=200 conv=notrunc 2>/dev/null # payload damaged
CSGTRACE_CL_CACHE=$cache render cc_3 0 hetero "$scene" --width 64 --height 48 --tile 16
if ! valid_bin "$bin"; then
    ko "program cache: the damaged file was not replaced"
elif same "$T/cc_1.pfm" "$T/cc_3.pfm"; then
    ok "program cache: a damaged binary is ignored and replaced, same image"
else
    ko "program cache: damaged binary: $(head -c 300 "$T/cc_3.err")"
fi
head -c 100 "$bin" >"$bin.cut" && mv "$bin.cut" "$bin" # torn
CSGTRACE_CL_CACHE=$cache render cc_4 0 hetero "$scene" --width 64 --height 48 --tile 16
same "$T/cc_1.pfm" "$T/cc_4.pfm" && valid_bin "$bin" &&
    ok "program cache: a torn binary is ignored and replaced" || ko "program cache: torn binary"
# another program's entry under this one's name (a foreign file: its
# header names its own key), and one whose key is rewritten to this name
# (its digest, of the other key and the payload, no longer holds):
# refused and rebuilt, the same image
CSGTRACE_CL_CACHE=$cache render cc_b 0 hetero "$T/gen_1.pov" --width 64 --height 48 --tile 16
other=$(ls "$cache"/*.clbin | grep -v "$bin")
cp "$other" "$bin"
CSGTRACE_CL_CACHE=$cache render cc_f 0 hetero "$scene" --width 64 --height 48 --tile 16
same "$T/cc_1.pfm" "$T/cc_f.pfm" && valid_bin "$bin" && ! cmp -s "$other" "$bin" &&
    ok "program cache: another program's entry under this name is refused and rebuilt" ||
    ko "program cache: foreign entry: $(head -c 300 "$T/cc_f.err")"
python3 -c "
import sys
a, b = open(sys.argv[1], 'rb').read(), open(sys.argv[2], 'rb').read()
open(sys.argv[2], 'wb').write(a[:16] + b[16:48] + a[48:])" "$other" "$bin"
CSGTRACE_CL_CACHE=$cache render cc_r 0 hetero "$scene" --width 64 --height 48 --tile 16
same "$T/cc_1.pfm" "$T/cc_r.pfm" && valid_bin "$bin" && ! cmp -s "$other" "$bin" &&
    ok "program cache: a re-keyed entry (the digest no longer holds) is refused and rebuilt" ||
    ko "program cache: re-keyed entry: $(head -c 300 "$T/cc_r.err")"
# a FIFO where the entry should be: not opened for reading (it would block
# for ever), refused, and the render goes on
rm -f "$bin" && mkfifo "$bin"
CSGTRACE_CL_CACHE=$cache timeout 60 "$BIN" render "$scene" -o "$T/cc_p.pfm" --mode hetero --fill off \
    --width 64 --height 48 --tile 16 >/dev/null 2>"$T/cc_p.err"
rc=$?
[ $rc = 0 ] && same "$T/cc_1.pfm" "$T/cc_p.pfm" &&
    ok "program cache: a FIFO in place of an entry: no hang, the same image" ||
    ko "program cache: FIFO entry: exit $rc (124: it hung), $(head -c 300 "$T/cc_p.err")"
rm -f "$bin"
# a cache folder others may write: not used, one warning, the same image
chmod 777 "$cache"
CSGTRACE_CL_CACHE=$cache render cc_w 0 hetero "$scene" --width 64 --height 48 --tile 16
grep -q "program cache is not used: others may write in $cache" "$T/cc_w.err" &&
    same "$T/cc_1.pfm" "$T/cc_w.pfm" && [ ! -e "$bin" ] &&
    ok "program cache: a folder others may write is not used, with one warning" ||
    ko "program cache: shared folder used, or no warning: $(head -c 300 "$T/cc_w.err")"
chmod 700 "$cache"
CSGTRACE_CL_CACHE=off HOME="$T/home-off" XDG_CACHE_HOME= render cc_5 0 hetero "$scene" --width 64 --height 48 --tile 16
same "$T/cc_1.pfm" "$T/cc_5.pfm" && [ ! -e "$T/home-off" ] &&
    ok "program cache: CSGTRACE_CL_CACHE=off writes nothing" || ko "program cache: off still wrote $(ls -R "$T/home-off" 2>&1 | head -3)"
CSGTRACE_CL_CACHE= HOME="$T/home" XDG_CACHE_HOME= render cc_6 0 hetero "$scene" --width 64 --height 48 --tile 16
ls "$T/home/.cache/csgtrace/"*.clbin >/dev/null 2>&1 && same "$T/cc_1.pfm" "$T/cc_6.pfm" &&
    ok "program cache: defaults to \$HOME/.cache/csgtrace" || ko "program cache: nothing in \$HOME/.cache/csgtrace"
touch "$T/not-a-folder"
CSGTRACE_CL_CACHE="$T/not-a-folder/sub" render cc_7 0 hetero "$scene" --width 64 --height 48 --tile 16
rc=$?
[ $rc = 0 ] && same "$T/cc_1.pfm" "$T/cc_7.pfm" && [ ! -s "$T/cc_7.err" ] &&
    ok "program cache: a cache that cannot be written: same image, no message" ||
    ko "program cache: unwritable cache: exit $rc, $(head -c 300 "$T/cc_7.err")"

# --- the fill: with the OpenCL build delayed (a test hook), workers render
#     whole tiles from the bottom up meanwhile; the pass does the rest ---
fill_check() { # fill_check NAME SERIAL EXPECTED_CLAIMED -> 0 when the image and the counts hold
    # (the fill's claimed tiles: rendered whole, or culled by the master)
    same "$T/$2.pfm" "$T/$1.pfm" && json "$T/$1.json" "j['tiles_filled'] + j['tiles_culled'] == $3 and
        j['tiles_sent'] + j['tiles_degenerate'] == j['tiles_total'] and
        j['pixels_hit'] == $(python3 -c "import json; print(json.load(open('$T/$2.json'))['pixels_hit'])") and
        j['rays']['primary'] == $(python3 -c "import json; print(json.load(open('$T/$2.json'))['rays']['primary'])")"
}
CSGTRACE_TEST_CL_DELAY_MS=1500 render fa 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16 --fill on \
    --pass always
fill_check fa s_2 30 && json "$T/fa.json" "j['slices'] == 0 and j['device'] == '' and
    j['tiles_degenerate'] == j['tiles_culled']" &&
    ok "fill: the build delayed, the workers render every tile (no pass): == serial, hits and rays counted" ||
    ko "fill, every tile: $(head -c 300 "$T/fa.err")"
CSGTRACE_TEST_CL_DELAY_MS=300 CSGTRACE_TEST_FILL_TILES=7 render fb 3 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --tile-log "$T/fb.log" --fill on --pass always
if fill_check fb s_2 7 && json "$T/fb.json" "j['slices'] > 0" && python3 - "$T/fb.log" <<'PY'
import json, sys
items = [json.loads(l) for l in open(sys.argv[1])]
claimed = sorted(i["tile"] for i in items if i["tile"] >= 23)
assert claimed == list(range(23, 30)), claimed
assert all(i["fill"] or i["skipped"] for i in items if i["tile"] >= 23)
assert not any(i["fill"] for i in items if i["tile"] < 23)
assert all(i["estimate"] is None and not i["skipped"] for i in items if i["fill"])
assert all(i["estimate"] is not None for i in items if not i["fill"] and not i["skipped"])
PY
then
    ok "fill: 7 tiles filled (the last 7, no estimate), the pass the others: == serial, hits counted"
else
    ko "fill, 7 tiles: $(head -c 300 "$T/fb.err")"
fi
CSGTRACE_TEST_CL_DELAY_MS=300 CSGTRACE_TEST_FILL_TILES=5 render fc 0 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on --pass always
fill_check fc s_2 5 && ok "fill without workers: the master renders 5 tiles itself, the pass the rest: == serial" ||
    ko "fill, one process: $(head -c 300 "$T/fc.err")"
CSGTRACE_TEST_CL_DELAY_MS=1500 render fd 3 hetero "$T/gen_1.pov" --width 96 --height 72 --spp 3 --tile 16 --fill on \
    --pass always
fill_check fd ss3 30 && ok "fill with --spp 3: == serial, 3 primary rays a pixel" || ko "fill, --spp 3: $(head -c 300 "$T/fd.err")"
"$BIN" render "$T/gen_1.pov" -o "$T/fe.pfm" --mode hetero --fill maybe >/dev/null 2>"$T/fe.err"
[ $? -eq 2 ] && grep -q -- "--fill" "$T/fe.err" && ok "--fill maybe: a usage error (exit 2)" || ko "--fill maybe: $(head -c 300 "$T/fe.err")"

# --- the fill's degenerate tiles, without any pass: the master proves a
#     tile empty with the workers' own frustum culling (no object may meet
#     any of its rays) and fills it with the background instead of sending
#     it; homo sends every tile; a sky_sphere (a missed ray's colour then
#     depends on its direction) culls nothing ---
"$BIN" gen spheres --count 6 --occupancy 0.15 --seed 9 --width 160 --height 120 -o "$T/sparse.pov" >/dev/null
render cu_s 0 serial "$T/sparse.pov" --width 160 --height 120 --tile 16
render cu_x 3 hetero "$T/sparse.pov" --width 160 --height 120 --tile 16 --fill on
render cu_h 3 homo "$T/sparse.pov" --width 160 --height 120 --tile 16
render cu_1 0 hetero "$T/sparse.pov" --width 160 --height 120 --tile 16 --fill on
same "$T/cu_s.pfm" "$T/cu_x.pfm" && same "$T/cu_s.pfm" "$T/cu_h.pfm" && same "$T/cu_s.pfm" "$T/cu_1.pfm" &&
    json "$T/cu_x.json" "j['cl_open'] == 'never' and 10 <= j['tiles_culled'] == j['tiles_degenerate'] and
        0 < j['cull_s'] < j['wall_s'] and
        j['tiles_sent'] + j['tiles_culled'] == j['tiles_total'] == 80 and j['tiles_filled'] == j['tiles_sent']" &&
    json "$T/cu_1.json" "j['tiles_culled'] == $(python3 -c "import json; print(json.load(open('$T/cu_x.json'))['tiles_culled'])")" &&
    json "$T/cu_h.json" "j['tiles_culled'] == 0 and j['tiles_sent'] == 80 and j['cull_s'] == 0 and
        j['guess_cpu_s'] == 0" &&
    ok "fill: empty tiles culled by the master, never sent ($(python3 -c "import json; print(json.load(open('$T/cu_x.json'))['tiles_culled'])") of 80): hetero == homo == serial, with and without workers" ||
    ko "fill, culled tiles: $(head -c 300 "$T/cu_x.err")"
{ cat "$T/sparse.pov"; echo 'sky_sphere { pigment { gradient y color_map { [0 color rgb <0.2,0.3,0.9>] [1 color rgb 1] } } }'; } >"$T/sparse_sky.pov"
render cu_ss 0 serial "$T/sparse_sky.pov" --width 160 --height 120 --tile 16
render cu_sx 3 hetero "$T/sparse_sky.pov" --width 160 --height 120 --tile 16 --fill on
same "$T/cu_ss.pfm" "$T/cu_sx.pfm" && json "$T/cu_sx.json" "j['tiles_culled'] == 0 and j['tiles_degenerate'] == 0" &&
    ok "fill with a sky_sphere: no tile culled (what a miss sees depends on its direction): == serial" ||
    ko "fill, sky_sphere: $(head -c 300 "$T/cu_sx.err")"

# --- --pass auto (the default): rank 0 guesses the frame's primary rays' work from a
#     sample; a frame too small for the pass to pay never opens the device
#     (the fill renders it all); one that pays (here: a test threshold of
#     1 ms) opens it, and the pass takes the tiles the fill leaves ---
render pa 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16 --fill on
fill_check pa s_2 30 && json "$T/pa.json" "j['cl_open'] == 'never' and j['device'] == '' and
    j['slices'] == 0 and 0 < j['pass_work_s'] < 0.16 and 0 < j['guess_cpu_s'] < j['wall_s']" &&
    ok "pass auto, a small frame: the device never opened, every tile filled: == serial" ||
    ko "pass auto, small frame: $(head -c 300 "$T/pa.err")"
CSGTRACE_TEST_PASS_PAYS_MS=1 CSGTRACE_TEST_FILL_TILES=5 render pb 3 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on
fill_check pb s_2 5 && json "$T/pb.json" "j['cl_open'] == 'work' and j['device'] != '' and
    j['slices'] > 0 and j['pass_work_s'] >= 0.001" &&
    ok "pass auto, a frame that pays: the device opened on the guess, the pass took the tiles left: == serial" ||
    ko "pass auto, opened: $(head -c 300 "$T/pb.err")"
CSGTRACE_TEST_PASS_PAYS_MS=1 CSGTRACE_TEST_FILL_TILES=5 render pc 0 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on
fill_check pc s_2 5 && json "$T/pc.json" "j['cl_open'] == 'work' and j['slices'] > 0" &&
    ok "pass auto without workers: the master renders 5 tiles while rank 0 guesses, the pass the rest: == serial" ||
    ko "pass auto, one process: $(head -c 300 "$T/pc.err")"
CSGTRACE_TEST_FILL_TILES=5 render pd 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16 --fill on
fill_check pd s_2 30 && json "$T/pd.json" "j['cl_open'] == 'never'" &&
    ok "pass auto, never: the fill goes past the tests' cap (no pass to wait for): == serial" ||
    ko "pass auto, never with a cap: $(head -c 300 "$T/pd.err")"
render pe 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16 --fill on --pass always
render pf 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16
same "$T/s_2.pfm" "$T/pe.pfm" &&
    json "$T/pe.json" "j['cl_open'] == 'start' and j['pass_work_s'] == 0 and j['guess_cpu_s'] == 0" &&
    json "$T/pf.json" "j['cl_open'] == 'start'" && json "$T/h_2.json" "j['cl_open'] == 'none'" &&
    ok "--pass always and --fill off open the device at once (cl_open start; homo: none)" ||
    ko "--pass always: $(head -c 300 "$T/pe.err")"
"$BIN" render "$T/gen_1.pov" -o "$T/pg.pfm" --mode hetero --pass sometimes >/dev/null 2>"$T/pg.err"
[ $? -eq 2 ] && grep -q -- "--pass" "$T/pg.err" && ok "--pass sometimes: a usage error (exit 2)" || ko "--pass sometimes: $(head -c 300 "$T/pg.err")"

# --- --pass auto whose device cannot be had (no OpenCL platform: an empty
#     ICD folder) on a frame that pays: the render goes on, the workers
#     rendering every tile, one warning saying why (whether OpenCL works
#     must not decide whether a frame renders: a small one never opens
#     it); asked for (--pass always), the pass's failure is the render's;
#     a bad OpenCL option stays an error under auto too ---
mkdir -p "$T/no-icd"
OCL_ICD_VENDORS=$T/no-icd CSGTRACE_TEST_PASS_PAYS_MS=1 render ph 3 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on
rc=$?
[ $rc -eq 0 ] && same "$T/s_2.pfm" "$T/ph.pfm" &&
    [ "$(grep -c "^csgtrace: warning: OpenCL: no platform found.*the render goes on without the OpenCL pass (--pass auto)" "$T/ph.err")" = 1 ] &&
    json "$T/ph.json" "j['cl_open'] == 'failed' and j['device'] == '' and j['slices'] == 0 and
        j['tiles_filled'] == j['tiles_sent'] == j['tiles_total'] - j['tiles_culled']" &&
    ok "pass auto, no OpenCL platform, a frame that pays: one warning, every tile filled, cl_open failed: == serial" ||
    ko "pass auto, no platform: exit $rc, $(head -c 300 "$T/ph.err")"
OCL_ICD_VENDORS=$T/no-icd CSGTRACE_TEST_PASS_PAYS_MS=1 render pi 0 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on
rc=$?
[ $rc -eq 0 ] && same "$T/s_2.pfm" "$T/pi.pfm" && json "$T/pi.json" "j['cl_open'] == 'failed'" &&
    ok "pass auto, no OpenCL platform, one process: the warning, == serial" ||
    ko "pass auto, no platform, one process: exit $rc, $(head -c 300 "$T/pi.err")"
OCL_ICD_VENDORS=$T/no-icd render pj 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16 \
    --fill on --pass always
rc=$?
[ $rc -eq 1 ] && grep -q "^csgtrace: error: OpenCL: no platform found" "$T/pj.err" && [ ! -e "$T/pj.pfm" ] &&
    ok "--pass always, no OpenCL platform: exit 1, the error, no image" ||
    ko "--pass always, no platform: exit $rc, $(head -c 300 "$T/pj.err")"
CSGTRACE_CL_SPECIALISE=bad CSGTRACE_TEST_PASS_PAYS_MS=1 render pk 3 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on
rc=$?
[ $rc -eq 1 ] && grep -q "CSGTRACE_CL_SPECIALISE must be 0 or 1" "$T/pk.err" && [ ! -e "$T/pk.pfm" ] &&
    ok "pass auto with a bad OpenCL option: still an error (exit 1)" ||
    ko "pass auto, bad option: exit $rc, $(head -c 300 "$T/pk.err")"

# --- a scene larger than the device's largest buffer (a GPU too small for
#     it; CSGTRACE_TEST_CL_MAX_ALLOC pretends one): under --pass auto the
#     pass is given up as a device that cannot be had, one warning naming
#     both sizes, the workers rendering every tile; asked for, an error
#     (the fill capped: the pass must begin, and the cap must lift) ---
CSGTRACE_TEST_FILL_TILES=5 CSGTRACE_TEST_CL_MAX_ALLOC=1000 CSGTRACE_TEST_PASS_PAYS_MS=1 \
    render pl 3 hetero "$T/gen_2.pov" \
    --width 96 --height 72 --tile 16 --fill on
rc=$?
[ $rc -eq 0 ] && same "$T/s_2.pfm" "$T/pl.pfm" &&
    [ "$(grep -c "^csgtrace: warning: OpenCL: the flattened scene, [0-9]* bytes, is larger than device \".*\"'s largest buffer, 1000 bytes (CL_DEVICE_MAX_MEM_ALLOC_SIZE): the render goes on without the OpenCL pass (--pass auto)" "$T/pl.err")" = 1 ] &&
    json "$T/pl.json" "j['cl_open'] == 'failed' and j['device'] == '' and j['slices'] == 0 and
        j['pass_s'] == 0 and j['tiles_filled'] == j['tiles_sent'] == j['tiles_total'] - j['tiles_culled']" &&
    ok "pass auto, a scene larger than the device's buffers: one warning, every tile filled: == serial" ||
    ko "pass auto, scene over the device's buffers: exit $rc, $(head -c 300 "$T/pl.err")"
CSGTRACE_TEST_FILL_TILES=5 CSGTRACE_TEST_CL_MAX_ALLOC=1000 render pm 3 hetero "$T/gen_2.pov" --width 96 --height 72 --tile 16 \
    --fill on --pass always
rc=$?
[ $rc -eq 1 ] && grep -q "^csgtrace: error: OpenCL: the flattened scene, [0-9]* bytes, is larger than" "$T/pm.err" &&
    [ ! -e "$T/pm.pfm" ] &&
    ok "--pass always, a scene larger than the device's buffers: exit 1, the error, no image" ||
    ko "--pass always, scene over the device's buffers: exit $rc, $(head -c 300 "$T/pm.err")"

# --- the generator meets its occupancy within +-1 point (sample of the grid) ---
for spec in "10 0.2 11" "30 0.5 12" "50 0.8 13"; do
    set -- $spec
    scene="$T/occ_$3.pov"
    "$BIN" gen spheres --count "$1" --occupancy "$2" --seed "$3" --width 384 --height 384 -o "$scene" >/dev/null
    render occ_$3 0 serial "$scene" --width 384 --height 384 --depth 1
    if json "$T/occ_$3.json" "abs(j['occupancy'] - $2) <= 0.01"; then
        ok "gen: $1 spheres, target $2: occupancy $(python3 -c "import json;print(round(json.load(open('$T/occ_$3.json'))['occupancy'],4))")"
    else
        ko "gen: $1 spheres, target $2: occupancy off by more than 1 point"
    fi
done
"$BIN" gen spheres --count 10 --occupancy 0.5 --seed 7 --width 64 --height 64 -o "$T/g1.pov" >/dev/null
"$BIN" gen spheres --count 10 --occupancy 0.5 --seed 7 --width 64 --height 64 -o "$T/g2.pov" >/dev/null
cmp -s "$T/g1.pov" "$T/g2.pov" && ok "gen: same seed, same file" || ko "gen: same seed gave different files"
"$BIN" gen spheres --count 10 --occupancy 0.5 --seed 8 --width 64 --height 64 -o "$T/g3.pov" >/dev/null
cmp -s "$T/g1.pov" "$T/g3.pov" && ko "gen: another seed gave the same file" || ok "gen: another seed, another file"
povray +W64 +H64 -D -A +O"$T/g1.png" "$T/g1.pov" >/dev/null 2>&1 && ok "gen output renders in POV-Ray 3.7" || ko "POV-Ray rejects the generated scene"

e2e_finish
