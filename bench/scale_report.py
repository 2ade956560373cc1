#!/usr/bin/env python3
"""scale_report.py CSV OUTDIR — the simulated grid (bench/scale.sh) into the
plot data (scale_eff.dat, scale_tile.dat), the plots (plot_scale*.gp) and
tables.md (the tables bench/SCALE.md quotes)."""
import csv
import math
import os
import subprocess
import sys

NETS = ("ib", "gige")
WORKERS = (16, 64, 256, 1024)


def rows(path):
    out = []
    for r in csv.DictReader(open(path)):
        if r["makespan_s"]:
            for k in ("makespan_s", "serial_s", "efficiency", "master_busy", "pass_scale"):
                r[k] = float(r[k])
            for k in ("size", "workers", "tile"):
                r[k] = int(r[k])
            out.append(r)
    return out


def main_grid(data, net, mode, workers):
    """The 4096 rows of the main grid: homo raster, hetero cost at pass 0.01."""
    want = ("raster", 1.0) if mode == "homo" else ("cost", 0.01)
    return [r for r in data if r["size"] == 4096 and r["network"] == net and r["mode"] == mode
            and r["workers"] == workers and (r["schedule"], r["pass_scale"]) == want]


def best(data, net, mode, workers):
    pts = main_grid(data, net, mode, workers)
    return max(pts, key=lambda r: r["efficiency"]) if pts else None


def fmt(x, spec=".3f"):
    return "n/a" if x is None else format(x, spec)


def best_tiles(data):
    lines = ["## Best tile size (4096x4096; tiles 32, 64, 128 simulated)", "",
             "| workers | " + " | ".join(f"{n} {m}" for n in NETS for m in ("homo", "hetero")) + " |",
             "| --- |" + " --- |" * 4]
    for w in WORKERS:
        cells = []
        for n in NETS:
            for m in ("homo", "hetero"):
                b = best(data, n, m, w)
                cells.append(f"{b['tile']} ({100 * b['efficiency']:.0f} %)" if b else "n/a")
        lines.append(f"| {w} | " + " | ".join(cells) + " |")
    return lines


def schedulers(data):
    """The four schedulers at 256 workers (4096, ib, tile 64); tail = makespan
    beyond perfect balance, makespan - serial_s / workers."""
    lines = ["## Schedulers at 256 workers (4096x4096, InfiniBand, tile 64)", "",
             "| mode | schedule | pass x | makespan [s] | tail beyond balance [s] | efficiency |",
             "| --- | --- | --- | --- | --- | --- |"]
    seen = set()
    for r in data:
        key = (r["mode"], r["schedule"], r["pass_scale"])
        if (r["size"] == 4096 and r["workers"] == 256 and r["network"] == "ib" and r["tile"] == 64
                and key not in seen):
            seen.add(key)
            tail = r["makespan_s"] - r["serial_s"] / r["workers"]
            lines.append(f"| {r['mode']} | {r['schedule']} | {r['pass_scale']:g} | "
                         f"{r['makespan_s']:.4f} | {tail:.4f} | {100 * r['efficiency']:.1f} % |")
    return lines


def tables(data):
    lines = best_tiles(data) + [""] + schedulers(data) + [""] + ["## Efficiency at 4096x4096, the best tile of each point", "",
             "| network | mode | workers | best tile | makespan [s] | efficiency | master busy |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for net in NETS:
        for mode in ("homo", "hetero"):
            for w in WORKERS:
                b = best(data, net, mode, w)
                if b:
                    lines.append(f"| {net} | {mode} | {w} | {b['tile']} | {b['makespan_s']:.3f} "
                                 f"| {100 * b['efficiency']:.1f} % | {100 * b['master_busy']:.0f} % |")
    lines += ["", "## Every simulated point", "",
              "| size | workers | network | mode | schedule | tile | pass x | makespan [s] | "
              "serial [s] | efficiency | master busy |", "|" + " --- |" * 11]
    for r in data:
        lines.append(f"| {r['size']} | {r['workers']} | {r['network']} | {r['mode']} | "
                     f"{r['schedule']} | {r['tile']} | {r['pass_scale']:g} | {r['makespan_s']:.3f} | "
                     f"{r['serial_s']:.2f} | {100 * r['efficiency']:.1f} % | "
                     f"{100 * r['master_busy']:.0f} % |")
    return "\n".join(lines) + "\n"


def plot_data(data, out):
    with open(os.path.join(out, "scale_eff.dat"), "w") as f:
        f.write("workers ib_homo ib_hetero gige_homo gige_hetero\n")
        for w in WORKERS:
            vals = [best(data, n, m, w) for n in NETS for m in ("homo", "hetero")]
            f.write(f"{w} " + " ".join(fmt(v and v["efficiency"], ".4f") if v else "nan"
                                       for v in vals) + "\n")
    tiles = sorted({r["tile"] for r in data if r["size"] == 4096})
    cols = [(n, w) for n in NETS for w in WORKERS]
    with open(os.path.join(out, "scale_tile.dat"), "w") as f:
        f.write("tile " + " ".join(f"{n}_{w}w" for n, w in cols) + "\n")
        for t in tiles:
            cells = []
            for n, w in cols:
                pts = [r for r in main_grid(data, n, "homo", w) if r["tile"] == t]
                cells.append(f"{pts[0]['makespan_s']:.4f}" if pts else "nan")
            f.write(f"{t} " + " ".join(cells) + "\n")


def main():
    data = rows(sys.argv[1])
    out = sys.argv[2]
    open(os.path.join(out, "tables.md"), "w").write(tables(data))
    plot_data(data, out)
    bench = os.path.dirname(os.path.abspath(__file__))
    for gp in ("plot_scale.gp", "plot_scale_tile.gp"):
        subprocess.run(["gnuplot", "-e", f"term='pngcairo'; bench='{bench}'",
                        os.path.join(bench, gp)], cwd=out, check=False)


if __name__ == "__main__":
    main()
