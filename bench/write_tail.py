#!/usr/bin/env python3
"""write_tail.py — what writing the image costs a render, binary against
binary: the paper's scene (`csgtrace gen spheres --count 50 --occupancy
0.5 --seed 1`) rendered by each binary of --bins to each format, under
mpirun with each rank count of --ranks (1: serial), R rounds interleaved
(every binary, format and rank count once, then again).  Prints per
configuration the medians (min-max) of the frame (wall_s), the tile phase
(tile_phase_s) and the write tail after the last tile (write_s), the
bands written during the tiles (write_bands_early / write_bands), and the
paired ratio of the frames (each round's frame of a binary over the first
binary's), and writes every row to --csv.  Every image of a configuration
is checked against the first binary's (idiff: the same pixels).

Usage: bench/write_tail.py --bins OLD,NEW [--formats exr,tif,png]
           [--ranks 2,3] [--size 4096] [--rounds 3] [--out DIR] [--csv FILE]
"""
import argparse
import csv
import json
import os
import shlex
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def render(binary, scene, size, fmt, ranks, out, stats, mpirun):
    cmd = [binary, "render", scene, "--width", str(size), "--height", str(size), "-o", out,
           "--stats", stats]
    if ranks <= 1:
        cmd += ["--mode", "serial"]
    else:
        cmd = shlex.split(mpirun) + ["-np", str(ranks)] + cmd + ["--mode", "homo"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("write_tail.py: %s failed (exit %d): %s"
                 % (" ".join(cmd), r.returncode, r.stderr[-400:]))
    with open(stats) as f:
        return json.load(f)


def same_pixels(a, b):
    return subprocess.run(["idiff", "-fail", "0", "-warn", "0", a, b],
                          capture_output=True).returncode == 0


def spread(values):
    return "%.3f (%.3f-%.3f)" % (statistics.median(values), min(values), max(values))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bins", required=True)
    ap.add_argument("--formats", default="exr,tif,png")
    ap.add_argument("--ranks", default="2,3")
    ap.add_argument("--size", type=int, default=4096)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "bench-write"))
    ap.add_argument("--csv", default="")
    ap.add_argument("--mpirun", default="mpirun --oversubscribe --bind-to none")
    args = ap.parse_args()
    bins = args.bins.split(",")
    formats = args.formats.split(",")
    ranks = [int(r) for r in args.ranks.split(",")]
    os.makedirs(args.out, exist_ok=True)
    scene = os.path.join(args.out, "s50.pov")
    subprocess.run([bins[-1], "gen", "spheres", "--count", "50", "--occupancy", "0.5", "--seed",
                    "1", "--width", "2048", "--height", "2048", "-o", scene],
                   check=True, capture_output=True)
    rows = []
    for rnd in range(args.rounds):
        for fmt in formats:
            for np_ in ranks:
                for b, binary in enumerate(bins):
                    out = os.path.join(args.out, "b%d-np%d.%s" % (b, np_, fmt))
                    stats = os.path.join(args.out, "b%d-np%d-%s-r%d.json" % (b, np_, fmt, rnd))
                    d = render(binary, scene, args.size, fmt, np_, out, stats, args.mpirun)
                    first = os.path.join(args.out, "b0-np%d.%s" % (np_, fmt))
                    rows.append({"round": rnd, "bin": binary, "b": b, "format": fmt, "ranks": np_,
                                 "wall_s": d["wall_s"], "tile_phase_s": d["tile_phase_s"],
                                 "write_s": d["write_s"], "write_bands": d["write_bands"],
                                 "write_bands_early": d["write_bands_early"],
                                 "same": b == 0 or same_pixels(first, out)})
                    print("round %d %s np %d %s: wall %.3f tile %.3f write %.3f" %
                          (rnd, fmt, np_, binary, d["wall_s"], d["tile_phase_s"], d["write_s"]),
                          file=sys.stderr)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)
    print("| format | ranks | binary | frame s | tile phase s | write tail s | bands early "
          "| frame / first binary's (paired) | same pixels |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---|")
    for fmt in formats:
        for np_ in ranks:
            base = {r["round"]: r["wall_s"] for r in rows
                    if r["format"] == fmt and r["ranks"] == np_ and r["b"] == 0}
            for b, binary in enumerate(bins):
                sel = [r for r in rows if r["format"] == fmt and r["ranks"] == np_ and r["b"] == b]
                ratios = [r["wall_s"] / base[r["round"]] for r in sel]
                print("| %s | %d | %s | %s | %s | %s | %d/%d | %s | %s |" % (
                    fmt, np_, binary, spread([r["wall_s"] for r in sel]),
                    spread([r["tile_phase_s"] for r in sel]), spread([r["write_s"] for r in sel]),
                    statistics.median([r["write_bands_early"] for r in sel]),
                    sel[0]["write_bands"], spread(ratios),
                    "yes" if all(r["same"] for r in sel) else "NO"))


if __name__ == "__main__":
    main()
