#!/usr/bin/env python3
"""progress.py — results over Open MPI's eager limit, measured: homo
renders of the paper's scene with tile 32 (answers under 4 KB), tile 64
and --batch 8 (answers over it), under `--mca btl_vader_single_copy_mechanism
none` (what a node without cross-memory attach gets: containers, some VMs)
and with Open MPI's default, by one or two programs (--old: the build
before the runtime made progress while computing), R rounds interleaved;
writes the tile phase, the frame and the workers' busy share, medians
(min-max), and each configuration's tile phase over tile 32's of the same
program and transport (the issue's target: tile 64 and --batch 8 as fast
as tile 32 within the spread).

Usage: bench/progress.py [--rounds R] [--size N] [--ranks K] [--old PATH]
                         [--report FILE.md]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = [("tile 32", ["--tile", "32"]), ("tile 64", ["--tile", "64"]),
           ("tile 32, --batch 8", ["--tile", "32", "--batch", "8"])]
TRANSPORTS = [("no single-copy", ["--mca", "btl_vader_single_copy_mechanism", "none"]),
              ("default", [])]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--ranks", type=int, default=3)
    ap.add_argument("--old", default="")
    ap.add_argument("--report", default=os.path.join(ROOT, "bench", "PROGRESS.md"))
    args = ap.parse_args()
    work = os.path.join(ROOT, "build", "bench-progress")
    os.makedirs(work, exist_ok=True)
    new = os.path.join(ROOT, "build", "csgtrace")
    bins = [("new", new)] + ([("old", args.old)] if args.old else [])
    scene = os.path.join(work, "s50.pov")
    subprocess.run([new, "gen", "spheres", "--count", "50", "--occupancy", "0.5", "--seed", "1",
                    "--width", str(args.size), "--height", str(args.size), "-o", scene],
                   check=True, capture_output=True)
    runs = {}
    t0 = time.monotonic()
    load0 = os.getloadavg()[0]
    for rnd in range(args.rounds):
        for bname, binary in bins:
            for tname, tflags in TRANSPORTS:
                for cname, cflags in CONFIGS:
                    stats = os.path.join(work, "st.json")
                    cmd = (["mpirun", "--oversubscribe", "--bind-to", "none", "-np",
                            str(args.ranks)] + tflags +
                           [binary, "render", scene, "-o", os.path.join(work, "x.png"), "--mode",
                            "homo", "--width", str(args.size), "--height", str(args.size),
                            "--stats", stats] + cflags)
                    p = subprocess.run(cmd, capture_output=True, text=True)
                    if p.returncode:
                        sys.exit("progress.py: %s: %s" % (" ".join(cmd), p.stderr[-500:]))
                    runs.setdefault((bname, tname, cname), []).append(json.load(open(stats)))
    elapsed = time.monotonic() - t0

    def med(key, field):
        return statistics.median(s[field] for s in runs[key])

    def cell(key, field, scale=1.0):
        v = [s[field] * scale for s in runs[key]]
        return "%.3f (%.3f-%.3f)" % (statistics.median(v), min(v), max(v))

    with open(args.report, "w") as f:
        f.write("# Results over the eager limit (bench/progress.py)\n\n")
        f.write("`bench/progress.py --rounds %d --size %d --ranks %d%s` on %s: homo, %dx%d, "
                "`csgtrace gen spheres --count 50 --occupancy 0.5 --seed 1`, %d ranks "
                "(master + %d workers), %d rounds interleaved, %.0f s; load average %.2f at the "
                "start, %.2f at the end, %d CPUs. Medians (min-max).\n\n"
                % (args.rounds, args.size, args.ranks, " --old OLD" if args.old else "",
                   time.strftime("%Y-%m-%d"), args.size, args.size, args.ranks, args.ranks - 1,
                   args.rounds, elapsed, load0, os.getloadavg()[0],
                   len(os.sched_getaffinity(0))))
        f.write("| program | transport | work items | tile phase s | / tile 32's | frame s | "
                "busy |\n|---|---|---|---|---:|---|---:|\n")
        for bname, _ in bins:
            for tname, _ in TRANSPORTS:
                base = med((bname, tname, "tile 32"), "tile_phase_s")
                for cname, _ in CONFIGS:
                    key = (bname, tname, cname)
                    f.write("| %s | %s | %s | %s | %.2f | %s | %.0f %% |\n"
                            % (bname, tname, cname, cell(key, "tile_phase_s"),
                               med(key, "tile_phase_s") / base, cell(key, "wall_s"),
                               100 * med(key, "busy_fraction")))
    print("progress.py: %s written (%.0f s)" % (args.report, elapsed))


if __name__ == "__main__":
    main()
