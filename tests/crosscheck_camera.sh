#!/usr/bin/env bash
# crosscheck_camera.sh — the camera statement against POV-Ray 3.7, in every
# order of its modifiers.
#
# tests/crosscheck_povray.sh renders csgtrace's export of a scene, whose
# camera is already resolved into plain vectors; here POV-Ray reads the
# camera statement itself.  Each generated scene is flat by construction
# (finish { ambient 1 diffuse 0 }, ambient_light 1, no light): the same
# objects, a checkered floor and a gradient, seen by one camera written with
# its modifiers (location, look_at, right, up, direction, sky, angle,
# orthographic, transforms) in one order, some repeated; the v31_ scenes
# say #version 3.1, where POV-Ray applies each item where it is written.  POV-Ray 3.7 and
# csgtrace render the very same file; tests/compare_images.py counts the
# pixels that agree (hit/miss alike, colours within 2.5/255); every scene
# must reach MIN_AGREEMENT (99.5 %).  The image is 160 x 120 and the scenes
# use right x*image_width/image_height, as POV-Ray's samples do.
#
# Usage: tests/crosscheck_camera.sh [--keep DIR]
# Environment: CSGTRACE (build/csgtrace), POVRAY (povray), MIN_AGREEMENT (99.5).
# Exit status: 0 every scene passed, 1 some failed, 77 POV-Ray or oiiotool
# missing (skipped).
set -u

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CSGTRACE=${CSGTRACE:-$ROOT/build/csgtrace}
POVRAY=${POVRAY:-povray}
MIN_AGREEMENT=${MIN_AGREEMENT:-99.5}
W=160
H=120

keep=""
if [ "${1:-}" = "--keep" ]; then
    keep=${2:?--keep needs a folder}
fi
for tool in "$POVRAY" oiiotool python3; do
    command -v "$tool" >/dev/null 2>&1 || { echo "crosscheck_camera: $tool not found: skipped"; exit 77; }
done
[ -x "$CSGTRACE" ] || { echo "crosscheck_camera: $CSGTRACE not built" >&2; exit 1; }
if [ -n "$keep" ]; then
    work=$keep
    mkdir -p "$work" || exit 1
else
    work=$(mktemp -d "${TMPDIR:-/tmp}/crosscheck_camera.XXXXXX") || exit 1
    trap 'rm -rf "$work"' EXIT
fi

# The camera statements: name, then the items in the order written.
cases=(
    "lookat_last|location <3, 4, -7> right x*image_width/image_height up y angle 55 look_at <0, 0.5, 0>"
    "lookat_first|look_at <0, 0.5, 0> location <3, 4, -7> right x*image_width/image_height up y angle 55"
    "right_after|location <3, 4, -7> look_at <0, 0.5, 0> right x*image_width/image_height up y angle 55"
    "angle_first|angle 40 location <3, 4, -7> look_at <0, 0.5, 0> right x*image_width/image_height"
    "direction_after|location <-4, 3, -6> look_at <0, 0, 0> direction 2*z right x*image_width/image_height"
    "sky_after|location <2, 5, -6> look_at <0, 0.5, 0> sky <0.3, 1, 0> right x*image_width/image_height angle 60"
    "sky_first|sky <0.3, 1, 0> location <2, 5, -6> right x*image_width/image_height look_at <0, 0.5, 0> angle 60"
    "repeated|location <9, 9, 9> look_at <5, 5, 5> right x angle 30 location <3, 4, -7> look_at <0, 0.5, 0> right x*image_width/image_height angle 55"
    "right_handed|location <3, 4, -7> look_at <0, 0.5, 0> right -x*image_width/image_height"
    "up_scaled|up 2*y location <1, 3, -8> right x*image_width/image_height look_at 0"
    "transformed|location <0, 2, -8> look_at <0, 0.5, 0> right x*image_width/image_height rotate 30*y translate <0.5, 0, 0>"
    "ortho_plain|orthographic location <3, 4, -7> look_at <0, 0.5, 0> right x*image_width/image_height"
    "ortho_sized|orthographic right 8*x*image_width/image_height up 8*y location <3, 4, -7> look_at <0, 0.5, 0>"
    "ortho_angle|orthographic angle 50 location <3, 4, -7> look_at <0, 0.5, 0> right x*image_width/image_height"
    "ortho_lookat_first|orthographic look_at <0, 0.5, 0> up 6*y right 6*x*image_width/image_height location <-3, 5, -7>"
    "perspective_kw|perspective location <3, 4, -7> angle 55 right x*image_width/image_height look_at <0, 0.5, 0> up y"
    "v31_item_by_item|location <3, 4, -7> look_at <0, 0.5, 0> right x*image_width/image_height up y angle 55"
    "v31_lookat_last|location <3, 4, -7> right x*image_width/image_height angle 55 look_at <0, 0.5, 0>"
)

write_scene() { # $1 file, $2 the camera items, $3 the #version
    cat >"$1" <<EOF
#version $3;
global_settings { assumed_gamma 1 ambient_light rgb 1 }
#default { finish { ambient 1 diffuse 0 } }
background { color rgb <0.1, 0.1, 0.2> }
camera { $2 }
plane { y, 0 pigment { checker color rgb <0.9, 0.9, 0.9> color rgb <0.2, 0.3, 0.2> } }
sphere { <0, 1, 0>, 1 pigment { color rgb <0.8, 0.2, 0.1> } }
box { <1.5, 0, -0.5>, <2.5, 1, 0.5> pigment { gradient y color_map { [0 color rgb <0, 0, 1>] [1 color rgb <1, 1, 0>] } } }
cylinder { <-2, 0, 0>, <-2, 2, 0>, 0.5 pigment { color rgb <0.1, 0.7, 0.3> } }
cone { <0, 0, 2>, 0.8, <0, 1.5, 2>, 0 pigment { color rgb <0.6, 0.2, 0.7> } }
EOF
}

passed=0
failed=0
for c in "${cases[@]}"; do
    name=${c%%|*}
    items=${c#*|}
    dir=$work/$name
    mkdir -p "$dir"
    version=3.7
    case $name in v31_*) version=3.1 ;; esac # POV-Ray's item-by-item camera
    write_scene "$dir/scene.pov" "$items" "$version"
    if ! (cd "$dir" && "$POVRAY" +Iscene.pov +Opov.png +FN +W$W +H$H -D -A File_Gamma=1.0 -P) \
            >"$dir/povray.log" 2>&1 || [ ! -s "$dir/pov.png" ]; then
        echo "$name: FAILED (povray)"
        tail -n 8 "$dir/povray.log" | sed 's/^/    | /'
        failed=$((failed + 1))
        continue
    fi
    if ! "$CSGTRACE" render "$dir/scene.pov" -o "$dir/ours.pfm" --mode serial --width $W \
            --height $H >"$dir/render.log" 2>&1; then
        echo "$name: FAILED (csgtrace render)"
        sed 's/^/    | /' "$dir/render.log"
        failed=$((failed + 1))
        continue
    fi
    if python3 "$ROOT/tests/compare_images.py" "$dir/pov.png" "$dir/ours.pfm" --name "$name" \
            --encoding-a linear --encoding-b linear --background 0.1,0.1,0.2 \
            --min "$MIN_AGREEMENT" --diff "$dir/diff.ppm"; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
    fi
done

echo "$passed passed, $failed failed"
[ -n "$keep" ] && echo "crosscheck_camera: scenes, images and logs kept in $work"
[ "$failed" -eq 0 ]
