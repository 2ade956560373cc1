#!/usr/bin/env bash
# e2e_image.sh — PNG, PPM and PFM written by csgtrace itself, band by band
# (host/output/stream.c):
#   - on every example scene and a random one (80x60): the PNG holds the
#     pixels of the file the image module writes ($CSGTRACE_IMAGE_WRITER=oiio,
#     idiff), and is a valid PNG to it; the PPM of one scene is the module's
#     byte for byte (a PPM has no freedom); the PFM (linear floats) of a
#     random scene holds the EXR's pixels (idiff reads both);
#   - a render to PNG, PPM or PFM maps neither csgtrace-image.so nor OpenImageIO
#     (LD_DEBUG=files) and works without the module; to EXR it needs it, and
#     says so;
#   - a folder in a PNG's place: refused before the first tile (exit 1,
#     the output named), nothing made, no journal, no temporary file (a
#     write that fails at the end: e2e_resume.sh's file-size limit).
# Usage: tests/e2e_image.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

SZ=(--width 80 --height 60 --mode serial)
"$BIN" gen spheres --count 30 --occupancy 0.4 --seed 11 --width 80 --height 60 \
    --materials opaque,reflective,transparent -o "$T/random.pov" >/dev/null || ko "gen"

bad=""
for scene in scenes/*.pov "$T/random.pov"; do
    name=$(basename "$scene" .pov)
    "$BIN" render "$scene" "${SZ[@]}" -o "$T/$name.png" >/dev/null 2>&1 &&
        CSGTRACE_IMAGE_WRITER=oiio "$BIN" render "$scene" "${SZ[@]}" -o "$T/$name-oiio.png" \
            >/dev/null 2>&1 || { bad+=" $name:failed"; continue; }
    same "$T/$name.png" "$T/$name-oiio.png" || bad+=" $name:pixels"
done
[ -z "$bad" ] && ok "every example scene and a random one: the PNG holds the module's pixels" ||
    ko "csgtrace's PNG against the module's:$bad"

"$BIN" render scenes/showcase.pov "${SZ[@]}" -o "$T/showcase.ppm" >/dev/null 2>&1 &&
    CSGTRACE_IMAGE_WRITER=oiio "$BIN" render scenes/showcase.pov "${SZ[@]}" \
        -o "$T/showcase-oiio.ppm" >/dev/null 2>&1 && cmp -s "$T/showcase.ppm" "$T/showcase-oiio.ppm" &&
    ok "the PPM is the module's, byte for byte" || ko "direct PPM differs from the module's"

"$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/random.pfm" >/dev/null 2>&1 &&
    "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/random.exr" >/dev/null 2>&1 &&
    idiff -fail 0 -warn 0 "$T/random.exr" "$T/random.pfm" >/dev/null 2>&1 &&
    ok "the PFM holds the EXR's float pixels" || ko "the PFM differs from the EXR"

# --- no module for PNG, PPM or PFM ---
for ext in png ppm pfm; do
    LD_DEBUG=files "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/mapped.$ext" \
        >/dev/null 2>"$T/ld.err"
    if [ -s "$T/mapped.$ext" ] && grep -q "file=.*libz" "$T/ld.err" &&
        ! grep -q -e "file=.*csgtrace-image.so" -e "file=.*OpenImageIO" "$T/ld.err"; then
        ok "a render to .$ext maps neither the image module nor OpenImageIO"
    else
        ko "a render to .$ext: $(grep -o -m 3 "file=[^ ]*\(image\|OpenImageIO\)[^ ]*" "$T/ld.err")"
    fi
done
NOMOD=$T/none/csgtrace-image.so
CSGTRACE_IMAGE_MODULE=$NOMOD "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/nomod.png" \
    >/dev/null 2>"$T/err" && cmp -s "$T/nomod.png" "$T/random.png" &&
    ok "a PNG render without the image module" || ko "PNG without the module: $(head -c 300 "$T/err")"
CSGTRACE_IMAGE_MODULE=$NOMOD "$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/nomod.exr" \
    >/dev/null 2>"$T/err"
rc=$?
[ $rc -eq 1 ] && grep -q "^csgtrace: error: $T/nomod.exr: .*image module.*none/csgtrace-image.so" "$T/err" &&
    [ ! -e "$T/nomod.exr" ] && ok "an EXR render without the module: exit 1, the module named" ||
    ko "EXR without the module: exit $rc, $(head -c 300 "$T/err")"

# --- a folder in the image's place: refused before any tile ---
mkdir -p "$T/out/dir.png"
"$BIN" render "$T/random.pov" "${SZ[@]}" -o "$T/out/dir.png" >/dev/null 2>"$T/err"
rc=$?
left=$(ls -A "$T/out" | tr '\n' ' ')
[ $rc -eq 1 ] && grep -q "^csgtrace: error: the output (-o) '$T/out/dir.png' is a folder" "$T/err" &&
    [ "$left" = "dir.png " ] &&
    ok "a folder in a PNG's place: exit 1, the output named, nothing made (no journal, no temporary file)" ||
    ko "a folder in the PNG's place: exit $rc, $(head -c 300 "$T/err"), left: $left"

e2e_finish
