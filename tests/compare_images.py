#!/usr/bin/env python3
"""compare_images.py — per-pixel agreement of two renders of a flat scene.

Used by tests/crosscheck_povray.sh to compare a POV-Ray 3.7 render with a
csgtrace render of the same "flat" export (every surface shows exactly its
pigment colour, see csg/export_pov.h).  A pixel agrees when both images
classify it the same way (background or object: equal to the background
colour within the tolerance, or not) and its colours agree within the
tolerance in every channel.

Reads 8-bit RGB/RGBA PNGs (POV-Ray's) and PFMs (csgtrace's float files,
each value turned into its 8-bit code as oiiotool's conversion does) itself,
with the standard library (zlib, struct); any other image with OpenImageIO's
Python bindings when they are installed (Debian: python3-openimageio), else
converted to 8-bit binary PPM with `oiiotool` (openimageio-tools).  (Starting
oiiotool costs ~0.3 s of loading OpenImageIO's libraries a file: most of a
cross-check's time.)  oiiotool copies pixel values as they are (no colour conversion),
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
import array
import math
import os
import struct
import subprocess
import zlib
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


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else (b if pb <= pc else c)


def read_png8(path):
    """(width, height, RGB bytes) of an 8-bit RGB or RGBA, non-interlaced
    PNG; None for any other PNG (or not a PNG)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    pos, idat, head = 8, [], None
    while pos + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + n
    if head is None:
        return None
    w, h, depth, ctype, _, _, interlace = head
    if depth != 8 or ctype not in (2, 6) or interlace != 0:
        return None
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = w * bpp
    out = bytearray()
    prev = bytearray(stride)
    for y in range(h):
        at = y * (stride + 1)
        ftype, line = raw[at], bytearray(raw[at + 1:at + 1 + stride])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            c = prev[i - bpp] if i >= bpp else 0
            b = prev[i]
            pred = (0, a, b, (a + b) // 2, paeth(a, b, c))[ftype] if ftype <= 4 else None
            if pred is None:
                raise ValueError(f"{path}: bad PNG filter {ftype}")
            line[i] = (line[i] + pred) & 255
        out += line if bpp == 3 else bytes(v for k, v in enumerate(line) if k % 4 != 3)
        prev = line
    return w, h, bytes(out)


def read_pfm(path):
    """(width, height, RGB codes) of a colour PFM, top row first, each float
    v turned into OpenImageIO's 8-bit code: (int)(clamp(v) * 255 + 0.5)."""
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    pos += 1
    if fields[0] != b"PF":
        raise ValueError(f"{path}: not a colour PFM")
    w, h, scale = int(fields[1]), int(fields[2]), float(fields[3])
    order = "<" if scale < 0 else ">"
    n = 3 * w * h
    vals = struct.unpack(f"{order}{n}f", data[pos:pos + 4 * n])
    # in single precision, as OpenImageIO computes it (0.7f * 255 is 178.5f)
    scaled = array.array("f", (min(max(v, 0.0), 1.0) * 255.0 for v in vals))
    codes = [int(x) for x in array.array("f", (x + 0.5 for x in scaled))]
    rows = [codes[r * 3 * w:(r + 1) * 3 * w] for r in range(h)]
    return w, h, [c for row in reversed(rows) for c in row]  # (PFM: bottom row first)


def read_image(path, decode):
    """(width, height, [linear floats, 3 a pixel]) of any image file."""
    table = [decode(c / 255.0) for c in range(256)]
    if path.lower().endswith(".pfm"):
        w, h, codes = read_pfm(path)
        return w, h, [table[c] for c in codes]
    png = read_png8(path) if path.lower().endswith(".png") else None
    if png is not None:
        w, h, pix = png
        return w, h, [table[c] for c in pix]
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
