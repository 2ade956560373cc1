#!/usr/bin/env python3
"""speed_report.py — the tables of bench/vs_povray.sh and bench/vs_embree.sh.

    speed_report.py RESULTS_DIR [--povray] [--embree] [-o OUT.md]

Reads RESULTS_DIR/vs_povray.csv and/or RESULTS_DIR/vs_embree.csv (both when
neither flag is given and the file exists) and prints Markdown tables; -o
also writes them, with the run's commit and CPU, to OUT.md.  Standard
library only; the CSV cells are read as data (numbers through float()).

Ratios are computed within one run and within one round: the speed-up of a
round is POV-Ray's trace time over csgtrace's in the same round, the
per-ray ratio csgtrace's rays per second over POV-Ray's in that round, the
Embree ratio Embree's Mrays/s over csgtrace's in that round; a table shows
the median over the rounds and the min-max spread, never a ratio of
medians taken from different runs.
"""
import csv
import math
import os
import statistics
import sys


def rows_of(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(row, key):
    try:
        v = float(row.get(key, ""))
    except ValueError:
        return float("nan")
    return v


def spread(values, fmt):
    values = [v for v in values if v == v]
    if not values:
        return "-"
    return f"{statistics.median(values):{fmt}} ({min(values):{fmt}}–{max(values):{fmt}})"


def geomean(values):
    values = [v for v in values if v == v and v > 0]
    return math.exp(sum(map(math.log, values)) / len(values)) if values else float("nan")


def md_table(header, lines):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(line) + " |" for line in lines]
    return "\n".join(out)


def povray_section(rows):
    groups = {}
    for r in rows:
        key = (r.get("scene", ""), int(num(r, "width")))
        groups.setdefault(key, {}).setdefault(r.get("round", ""), {})[r.get("renderer", "")] = r
    lines, speedups, perray = [], [], []
    for (scene, size), rounds in sorted(groups.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        pov_t, csg_t, pov_rate, csg_rate, sp, pr = [], [], [], [], [], []
        for by in rounds.values():
            p, c = by.get("povray"), by.get("csgtrace")
            if not p or not c:
                continue
            pt, ct = num(p, "trace_s"), num(c, "trace_s")
            prate, crate = num(p, "rays") / pt / 1e6, num(c, "rays") / ct / 1e6
            pov_t.append(pt)
            csg_t.append(ct)
            pov_rate.append(prate)
            csg_rate.append(crate)
            sp.append(pt / ct)
            pr.append(crate / prate)
        if not sp:
            continue
        speedups.append(statistics.median(sp))
        perray.append(statistics.median(pr))
        any_p = next(by["povray"] for by in rounds.values() if "povray" in by)
        any_c = next(by["csgtrace"] for by in rounds.values() if "csgtrace" in by)
        lines.append([scene, f"{size}²", str(len(sp)), spread(pov_t, ".3f"), spread(csg_t, ".3f"),
                      spread(sp, ".2f"), f"{num(any_p, 'rays') / 1e6:.2f}",
                      f"{num(any_c, 'rays') / 1e6:.2f}", spread(pov_rate, ".2f"),
                      spread(csg_rate, ".2f"), spread(pr, ".2f")])
    table = md_table(["scene", "size", "rounds", "POV-Ray trace s", "csgtrace trace s",
                      "speed-up", "POV-Ray Mrays", "csgtrace Mrays", "POV-Ray Mrays/s",
                      "csgtrace Mrays/s", "per-ray ratio"], lines)
    summary = (f"Geometric mean over the {len(speedups)} configurations of the median speed-up "
               f"(POV-Ray trace time / csgtrace trace time): {geomean(speedups):.2f}x "
               f"(min {min(speedups):.2f}x); of the median per-ray ratio (csgtrace rays/s / "
               f"POV-Ray rays/s): {geomean(perray):.2f}x (min {min(perray):.2f}x).") if speedups else ""
    return table + "\n\n" + summary


def embree_section(rows):
    groups = {}
    for r in rows:
        groups.setdefault(int(num(r, "count")), {}).setdefault(r.get("round", ""), {})[
            r.get("renderer", "")] = r
    lines = []
    for count, rounds in sorted(groups.items()):
        cs, es, ratio = [], [], []
        for by in rounds.values():
            c, e = by.get("csgtrace"), by.get("embree")
            if not c or not e:
                continue
            cs.append(num(c, "mrays_per_s"))
            es.append(num(e, "mrays_per_s"))
            ratio.append(es[-1] / cs[-1])
        if not ratio:
            continue
        any_c = next(by["csgtrace"] for by in rounds.values() if "csgtrace" in by)
        any_e = next(by["embree"] for by in rounds.values() if "embree" in by)
        lines.append([f"{count}", f"{int(num(any_c, 'width'))}²", str(len(ratio)),
                      spread(cs, ".2f"), spread(es, ".2f"), spread(ratio, ".2f"),
                      f"{int(num(any_c, 'hits'))} / {int(num(any_e, 'hits'))}"])
    return md_table(["spheres", "image", "rounds", "csgtrace Mrays/s", "Embree Mrays/s",
                     "Embree / csgtrace", "hits csgtrace / Embree"], lines)


def run_line(rows):
    if not rows:
        return ""
    r = rows[0]
    line = f"commit {r.get('commit', '?')}, {r.get('cpu', '?')}"
    loads = [num(x, "load") for x in rows]
    loads = [v for v in loads if v == v]
    if loads:  # the machine is shared: how busy it was during the runs
        line += (f"; 1-minute load average during the runs {statistics.median(loads):.2f} "
                 f"({min(loads):.2f}–{max(loads):.2f}) on {r.get('cores', '?')} cores")
    return line


def main(argv):
    args = argv[1:]
    if not args or args[0].startswith("-"):
        sys.exit("usage: speed_report.py RESULTS_DIR [--povray] [--embree] [-o OUT.md]")
    results, out_md = args[0], None
    want = {a for a in args[1:] if a in ("--povray", "--embree")}
    if "-o" in args:
        i = args.index("-o")
        if i + 1 >= len(args):
            sys.exit("speed_report.py: -o needs a file")
        out_md = args[i + 1]
    pov = rows_of(os.path.join(results, "vs_povray.csv"))
    emb = rows_of(os.path.join(results, "vs_embree.csv"))
    parts = []
    if pov and (not want or "--povray" in want):
        parts.append("## One core, trace to trace, against POV-Ray 3.7 +WT1 (bench/vs_povray.sh)\n\n"
                     + povray_section(pov) + "\n\nRun: " + run_line(pov))
    if emb and (not want or "--embree" in want):
        parts.append("## Primary rays against Embree rtcIntersect1, one core (bench/vs_embree.sh)\n\n"
                     + embree_section(emb) + "\n\nRun: " + run_line(emb))
    text = "\n\n".join(parts)
    print(text)
    if out_md:
        with open(out_md, "w") as f:
            f.write("# Speed: csgtrace against POV-Ray 3.7 and Embree\n\n"
                    "Written by `make bench-speed` (bench/speed_report.py); how each figure is "
                    "measured is in the headers of bench/vs_povray.sh and bench/vs_embree.sh.\n\n"
                    + text + "\n")


if __name__ == "__main__":
    main(sys.argv)
