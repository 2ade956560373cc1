#!/usr/bin/env python3
"""bench/accuracy.py — the plot and the summary of bench/accuracy.sh.

    python3 bench/accuracy.py accuracy.csv accuracy.png accuracy_summary.md

Reads the CSV (one row per scene x setting, the reference included),
marks for each scene the Pareto front of (wall time, RMSE) — the settings
that no other setting beats on both — plots time versus RMSE, one panel per
scene, with gnuplot (PNG), and writes a Markdown summary: per scene the
reference, the headline setting (float, depth 3, threshold 0.01, spp 1),
the Pareto front, and the average effect of each knob.  Standard library
only; gnuplot is called as a program.
"""
import csv
import math
import os
import statistics
import subprocess
import sys
import tempfile

RMSE_FLOOR = 1e-6  # an exact match is drawn here on the log axis


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("wall_s", "rmse", "max_abs", "over_1_255", "ref_wall_s", "speedup"):
            r[k] = float(r[k])
        r["psnr"] = float(r["psnr"]) if r["psnr"] != "inf" else math.inf
        r["depth"] = int(r["depth"])
        r["spp"] = int(r["spp"])
        r["reference"] = r["reference"] == "1"
    return rows


def pareto(rows):
    """Non-dominated rows on (wall_s, rmse), sorted by time."""
    front = []
    for r in sorted(rows, key=lambda r: (r["wall_s"], r["rmse"])):
        if not front or r["rmse"] < front[-1]["rmse"]:
            front.append(r)
    return front


def label(r):
    return "%s d%d t%s spp%d" % (r["precision"], r["depth"], r["threshold"], r["spp"])


def plot(scenes, by_scene, png):
    tmp = tempfile.mkdtemp(prefix="accuracy-")
    cols = 3
    nrows = (len(scenes) + cols - 1) // cols
    lines = [
        "set terminal pngcairo size %d,%d font 'sans,9'" % (420 * cols, 340 * nrows),
        "set output '%s'" % png,
        "set multiplot layout %d,%d title 'csgtrace: render time versus error "
        "(RMSE against double, depth 32, threshold 1e-6, max spp)'" % (nrows, cols),
        "set logscale xy",
        "set xlabel 'wall time (s)'",
        "set ylabel 'RMSE (linear)'",
        "set key bottom left font 'sans,8'",
        "set grid",
    ]
    for s in scenes:
        rows = [r for r in by_scene[s] if not r["reference"]]
        files = {}
        for prec in ("float", "double"):
            for spp in sorted({r["spp"] for r in rows}):
                fn = os.path.join(tmp, "%s-%s-%d.dat" % (s, prec, spp))
                with open(fn, "w") as f:
                    for r in rows:
                        if r["precision"] == prec and r["spp"] == spp:
                            f.write("%g %g\n" % (r["wall_s"], max(r["rmse"], RMSE_FLOOR)))
                files[(prec, spp)] = fn
        fr = os.path.join(tmp, "%s-front.dat" % s)
        with open(fr, "w") as f:
            for r in pareto(rows):
                f.write("%g %g\n" % (r["wall_s"], max(r["rmse"], RMSE_FLOOR)))
        ref = [r for r in by_scene[s] if r["reference"]][0]
        lines.append("set title '%s (reference %.2f s)'" % (s, ref["wall_s"]))
        plots = []
        for (prec, spp), fn in sorted(files.items()):
            pt = 7 if prec == "float" else 5
            lc = {1: "'#1f77b4'", 4: "'#2ca02c'"}.get(spp, "'#9467bd'") if prec == "float" \
                else {1: "'#d62728'", 4: "'#ff7f0e'"}.get(spp, "'#8c564b'")
            plots.append("'%s' using 1:2 with points pt %d ps 0.8 lc rgb %s title '%s spp %d'"
                         % (fn, pt, lc, prec, spp))
        plots.append("'%s' using 1:2 with linespoints lw 2 pt 6 ps 1.6 lc rgb 'black' "
                     "title 'Pareto front'" % fr)
        lines.append("plot " + ", ".join(plots))
    lines.append("unset multiplot")
    gp = os.path.join(tmp, "accuracy.gp")
    with open(gp, "w") as f:
        f.write("\n".join(lines) + "\n")
    subprocess.run(["gnuplot", gp], check=True)


def knob_effects(rows):
    """Average time ratio and RMSE change of each knob, other knobs fixed."""
    out = []
    key = lambda r: (r["precision"], r["depth"], r["threshold"], r["spp"])
    idx = {key(r): r for r in rows if not r["reference"]}

    def pairs(f):
        ps = []
        for k, r in idx.items():
            k2 = f(k)
            if k2 and k2 in idx:
                ps.append((r, idx[k2]))
        return ps

    def summarise(name, ps):
        if not ps:
            return
        ratio = statistics.median(b["wall_s"] / a["wall_s"] for a, b in ps)
        d_rmse = statistics.median(b["rmse"] - a["rmse"] for a, b in ps)
        worst = max(b["rmse"] - a["rmse"] for a, b in ps)
        out.append((name, len(ps), ratio, d_rmse, worst))

    summarise("double -> float", pairs(
        lambda k: ("float",) + k[1:] if k[0] == "double" else None))
    for d0, d1 in ((8, 5), (5, 3), (3, 2), (2, 1)):
        summarise("depth %d -> %d" % (d0, d1), pairs(
            lambda k, d0=d0, d1=d1: (k[0], d1, k[2] if d1 > 1 else "0", k[3])
            if k[1] == d0 else None))
    for t0, t1 in (("0", "0.001"), ("0.001", "0.01"), ("0.01", "0.1")):
        summarise("threshold %s -> %s" % (t0, t1), pairs(
            lambda k, t0=t0, t1=t1: (k[0], k[1], t1, k[3]) if k[2] == t0 and k[1] > 1 else None))
    summarise("spp 4 -> 1", pairs(
        lambda k: (k[0], k[1], k[2], 1) if k[3] == 4 else None))
    return out


def summary(scenes, by_scene, md):
    L = []
    L.append("Times: median of the runs' `wall_s` (serial, one core). Errors against the "
             "scene's reference (double, depth 32, threshold 1e-6, highest spp), linear EXR "
             "values: RMSE, PSNR (peak 1), max abs channel difference, share of pixels "
             "with a channel off by more than 1/255.\n")
    L.append("### Headline: float, depth 3, threshold 0.01, spp 1 against the reference\n")
    L.append("| scene | reference s | setting s | speed-up | RMSE | PSNR dB | max abs | "
             "pixels > 1/255 |")
    L.append("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for s in scenes:
        ref = [r for r in by_scene[s] if r["reference"]][0]
        h = [r for r in by_scene[s] if not r["reference"] and r["precision"] == "float"
             and r["depth"] == 3 and r["threshold"] == "0.01" and r["spp"] == 1]
        if not h:
            continue
        h = h[0]
        L.append("| %s | %.3f | %.3f | %.1fx | %.4g | %.1f | %.3g | %.2f%% |" % (
            s, ref["wall_s"], h["wall_s"], ref["wall_s"] / h["wall_s"], h["rmse"], h["psnr"],
            h["max_abs"], 100 * h["over_1_255"]))
    L.append("\n### What each knob buys (median over the grid, other knobs fixed)\n")
    L.append("| scene | change | pairs | time ratio (new/old) | median RMSE change | "
             "worst RMSE change |")
    L.append("| --- | --- | ---: | ---: | ---: | ---: |")
    for s in scenes:
        for name, n, ratio, d, worst in knob_effects(by_scene[s]):
            L.append("| %s | %s | %d | %.2f | %+.2g | %+.2g |" % (s, name, n, ratio, d, worst))
    L.append("\n### Pareto fronts (time, RMSE): the settings nothing beats on both\n")
    for s in scenes:
        rows = [r for r in by_scene[s] if not r["reference"]]
        L.append("- **%s**: " % s + "; ".join(
            "%s %.3f s RMSE %.3g" % (label(r), r["wall_s"], r["rmse"]) for r in pareto(rows)))
    with open(md, "w") as f:
        f.write("\n".join(L) + "\n")


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: accuracy.py accuracy.csv accuracy.png accuracy_summary.md")
    rows = load(sys.argv[1])
    scenes = []
    by_scene = {}
    for r in rows:
        if r["scene"] not in by_scene:
            scenes.append(r["scene"])
            by_scene[r["scene"]] = []
        by_scene[r["scene"]].append(r)
    plot(scenes, by_scene, sys.argv[2])
    summary(scenes, by_scene, sys.argv[3])


if __name__ == "__main__":
    main()
