#!/usr/bin/env python3
"""compare_images.py — per-pixel agreement of two renders of a flat scene.

Used by tests/crosscheck_povray.sh to compare a POV-Ray 3.7 render with a
csgtrace render of the same "flat" export (every surface shows exactly its
pigment colour, see csg/export_pov.h).  A pixel agrees when both images
classify it the same way (background or object: equal to the background
colour within the tolerance, or not) and its colours agree within the
tolerance in every channel.

Reads images with OpenImageIO's Python bindings when they are installed
(Debian: python3-openimageio), else converts them to 8-bit binary PPM with
`oiiotool` (openimageio-tools) and reads that; only the standard library is
needed.  oiiotool copies pixel values as they are (no colour conversion),
so each input's transfer encoding is given with --encoding-a/-b:
  linear   code/255                 (POV-Ray with File_Gamma=1.0; EXR)
  srgb     the sRGB curve           (POV-Ray 3.7's default PNG output)
  gamma2.2 code/255 ** 2.2

With --background none every pixel is compared by its colours alone (two
full renders, not flat ones).

Prints one line:  NAME: agreement 99.87% (N of M pixels) [details]
Exit status: 0 when agreement >= --min, 1 below, 2 on bad input.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile


def srgb_to_linear(c):
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


DECODERS = {
    "linear": lambda c: c,
    "srgb": srgb_to_linear,
    "gamma2.2": lambda c: c ** 2.2,
}


def read_ppm(path):
    """(width, height, bytes) of an 8-bit binary PPM (P6, maxval 255)."""
    with open(path, "rb") as f:
        data = f.read()
    fields = []
    pos = 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    pos += 1  # the single whitespace after maxval
    if fields[0] != b"P6" or int(fields[3]) != 255:
        raise ValueError(f"{path}: not an 8-bit binary PPM")
    w, h = int(fields[1]), int(fields[2])
    pix = data[pos:pos + 3 * w * h]
    if len(pix) != 3 * w * h:
        raise ValueError(f"{path}: truncated PPM")
    return w, h, pix


def read_image(path, decode):
    """(width, height, [linear floats, 3 a pixel]) of any image file."""
    try:
        import OpenImageIO as oiio  # type: ignore
    except ImportError:
        oiio = None
    if oiio is not None:
        buf = oiio.ImageBuf(path)
        spec = buf.spec()
        if buf.has_error or spec.nchannels < 3:
            raise ValueError(f"{path}: cannot read ({buf.geterror()})")
        px = buf.get_pixels(oiio.UINT8)
        codes = [int(v) for row in px for col in row for v in col[:3]]
        w, h = spec.width, spec.height
    else:
        with tempfile.TemporaryDirectory() as tmp:
            ppm = os.path.join(tmp, "img.ppm")
            r = subprocess.run(["oiiotool", path, "--ch", "R,G,B", "-d", "uint8", "-o", ppm],
                               capture_output=True, text=True)
            if r.returncode != 0:
                raise ValueError(f"{path}: oiiotool failed: {r.stderr.strip()}")
            w, h, pix = read_ppm(ppm)
            codes = list(pix)
    table = [decode(c / 255.0) for c in range(256)]
    return w, h, [table[c] for c in codes]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("a", help="reference image (POV-Ray)")
    ap.add_argument("b", help="image to check (csgtrace)")
    ap.add_argument("--name", default=None, help="label of the output line")
    ap.add_argument("--encoding-a", choices=DECODERS, default="linear")
    ap.add_argument("--encoding-b", choices=DECODERS, default="linear")
    ap.add_argument("--background", default="0,0,0",
                    help="linear r,g,b of the background (miss) colour, or 'none': "
                         "the colours alone are compared (a full render)")
    ap.add_argument("--tolerance", type=float, default=2.5 / 255,
                    help="largest per-channel difference, linear (default 2.5/255)")
    ap.add_argument("--min", type=float, default=99.5,
                    help="agreement in percent below which the exit status is 1")
    ap.add_argument("--diff", default=None,
                    help="write the mismatching pixels as a PPM (white: hit/miss, red: colour)")
    args = ap.parse_args()

    try:
        bg = None if args.background == "none" else [float(v) for v in args.background.split(",")]
        if bg is not None and len(bg) != 3:
            raise ValueError("--background needs r,g,b or none")
        wa, ha, pa = read_image(args.a, DECODERS[args.encoding_a])
        wb, hb, pb = read_image(args.b, DECODERS[args.encoding_b])
    except (ValueError, OSError) as e:
        print(f"compare_images: error: {e}", file=sys.stderr)
        return 2
    name = args.name or os.path.basename(args.b)
    if (wa, ha) != (wb, hb):
        print(f"{name}: agreement 0.00% (sizes differ: {wa}x{ha} vs {wb}x{hb})")
        return 1

    tol = args.tolerance
    total = wa * ha
    hitmiss = colour = hits_a = hits_b = 0
    diff = bytearray(3 * total) if args.diff else None
    for i in range(total):
        ca = pa[3 * i:3 * i + 3]
        cb = pb[3 * i:3 * i + 3]
        hit_a = bg is None or any(abs(ca[k] - bg[k]) > tol for k in range(3))
        hit_b = bg is None or any(abs(cb[k] - bg[k]) > tol for k in range(3))
        hits_a += hit_a
        hits_b += hit_b
        if hit_a != hit_b:
            hitmiss += 1
            if diff is not None:
                diff[3 * i:3 * i + 3] = b"\xff\xff\xff"
        elif any(abs(ca[k] - cb[k]) > tol for k in range(3)):
            colour += 1
            if diff is not None:
                diff[3 * i:3 * i + 3] = b"\xff\x00\x00"
    good = total - hitmiss - colour
    pct = 100.0 * good / total if total else 0.0
    shown = math.floor(pct * 100) / 100  # never print 99.50% for 99.497%
    print(f"{name}: agreement {shown:.2f}% ({good} of {total} pixels)"
          f" [hit/miss differ: {hitmiss}, colour differs: {colour};"
          f" object pixels {hits_a} vs {hits_b}]")
    if diff is not None:
        with open(args.diff, "wb") as f:
            f.write(b"P6\n%d %d\n255\n" % (wa, ha) + bytes(diff))
    return 0 if pct >= args.min else 1


if __name__ == "__main__":
    sys.exit(main())
