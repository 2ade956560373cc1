#!/usr/bin/env python3
"""node.py — one node, as a user runs it (make bench-node): the paper's
scene (`csgtrace gen spheres --count 50 --occupancy 0.5 --seed 1`) rendered
serially, then homo and hetero under mpirun with np = 2, 4, 8, ... up to
the node's CPUs and one more (the master is mostly idle), at each size,
tile size and output format, R rounds interleaved (every configuration
once, then again); writes bench/NODE.md with the machine's description and
per configuration the medians (min-max) of the frame, the tile phase and
the write tail, and:
  - the frame's speed-up over serial (serial wall / wall) and its
    efficiency (speed-up / workers),
  - the tile phase's speed-up (serial tile phase / tile phase) and
    efficiency,
  - the workers' busy share of their tile phase (the stats'
    busy_fraction),
  - the write tail's share of the wall (write_s / wall_s),
and whether every image of a size is the serial one, bit for bit.

Usage: bench/node.py [--rounds R] [--sizes 2048,4096] [--tiles 32,64]
                     [--formats png,exr] [--ranks 2,4,...] [--out DIR]
                     [--report FILE.md] [--bin PATH] [--mpirun "mpirun ..."]
  EXR runs only where the image module loads (OpenImageIO); the raw stats
  go to OUT (default build/bench-node), one JSON file a render.
"""
import argparse
import json
import os
import platform
import shlex
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sh(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def machine():
    """A few lines on the machine: CPU, cores, memory, GPU, OpenCL."""
    lines = []
    cpu = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    lines.append("- CPU: %s, %d CPUs usable (os.sched_getaffinity)"
                 % (cpu or platform.processor(), len(os.sched_getaffinity(0))))
    try:
        mem = [l for l in open("/proc/meminfo") if l.startswith("MemTotal")][0].split()[1]
        lines.append("- memory: %.1f GiB" % (int(mem) / 1048576))
    except (OSError, IndexError):
        pass
    if shutil.which("nvidia-smi"):
        gpu = sh(["nvidia-smi", "--query-gpu=name,memory.total", "--format=csv,noheader"])
        if gpu.returncode == 0 and gpu.stdout.strip():
            lines.append("- GPU: " + gpu.stdout.strip().replace("\n", "; "))
    if shutil.which("clinfo"):
        cl = sh(["clinfo", "-l"])
        if cl.returncode == 0:
            devs = [l.strip() for l in cl.stdout.splitlines() if "Device" in l]
            lines.append("- OpenCL: " + ("; ".join(devs) if devs else "no device"))
    lines.append("- system: %s %s" % (platform.system(), platform.release()))
    return lines


def render(args, scene, size, mode, ranks, tile, fmt, name):
    """One render; its stats (dict) and image path."""
    out = os.path.join(args.out, name)
    image, stats = out + "." + fmt, out + ".json"
    cmd = [args.bin, "render", scene, "-o", image, "--width", str(size), "--height", str(size),
           "--mode", mode, "--tile", str(tile), "--stats", stats]
    if mode != "serial":
        cmd = shlex.split(args.mpirun) + ["-np", str(ranks)] + cmd
    p = sh(cmd)
    if p.returncode != 0:
        sys.exit("node.py: %s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-800:]))
    return json.load(open(stats)), image


def same(a, b):
    return sh(["idiff", "-fail", "0", "-warn", "0", a, b]).returncode == 0


def spread(values):
    return statistics.median(values), min(values), max(values)


def cell(values, scale=1.0, fmt="%.3f"):
    m, lo, hi = spread([v * scale for v in values])
    return (fmt + " (" + fmt + "-" + fmt + ")") % (m, lo, hi)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--sizes", default="2048,4096")
    ap.add_argument("--tiles", default="32,64")
    ap.add_argument("--formats", default="png,exr")
    ap.add_argument("--ranks", default="")
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "bench-node"))
    ap.add_argument("--report", default=os.path.join(ROOT, "bench", "NODE.md"))
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "csgtrace"))
    ap.add_argument("--mpirun", default="mpirun --oversubscribe --bind-to none")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    cpus = len(os.sched_getaffinity(0))
    if args.ranks:
        ranks = [int(r) for r in args.ranks.split(",")]
    else:
        ranks, n = [], 2
        while n <= cpus:
            ranks.append(n)
            n *= 2
        ranks += [r for r in (cpus, cpus + 1) if r not in ranks]
    sizes = [int(s) for s in args.sizes.split(",")]
    tiles = [int(t) for t in args.tiles.split(",")]
    formats = args.formats.split(",")
    probe = os.path.join(args.out, "probe.exr")
    if "exr" in formats and sh([args.bin, "render", os.path.join(ROOT, "scenes", "showcase.pov"),
                                "-o", probe, "--width", "8", "--height", "8"]).returncode != 0:
        formats = [f for f in formats if f != "exr"]  # (no image module here)
    scene = os.path.join(args.out, "s50.pov")
    if sh([args.bin, "gen", "spheres", "--count", "50", "--occupancy", "0.5", "--seed", "1",
           "--width", "2048", "--height", "2048", "-o", scene]).returncode != 0:
        sys.exit("node.py: gen failed")
    configs = [(s, "serial", 1, t, f) for s in sizes for t in tiles for f in formats]
    configs += [(s, m, r, t, f) for s in sizes for r in ranks for m in ("homo", "hetero")
                for t in tiles for f in formats]
    runs = {c: [] for c in configs}
    identical = {}
    t0 = time.monotonic()
    for rnd in range(args.rounds):
        for c in configs:
            size, mode, r, tile, fmt = c
            name = "%d-%s-%d-t%d-%s-r%d" % (size, mode, r, tile, fmt, rnd)
            st, image = render(args, scene, size, mode, r, tile, fmt, name)
            runs[c].append(st)
            ref = os.path.join(args.out, "%d-serial-1-t%d-%s-r0.%s" % (size, tiles[0], fmt, fmt))
            if rnd == 0 and image != ref:
                identical[(size, fmt)] = identical.get((size, fmt), True) and same(ref, image)
            if rnd > 0 or image != ref:
                os.remove(image)
    elapsed = time.monotonic() - t0
    with open(args.report, "w") as f:
        f.write("# One node: frame, tile phase and write tail (bench/node.py)\n\n")
        f.write("Made by `make bench-node` (`bench/node.py --rounds %d --sizes %s --tiles %s "
                "--formats %s --ranks %s`) on %s, %d rounds interleaved, %.0f s in all.\n\n"
                % (args.rounds, args.sizes, args.tiles, ",".join(formats),
                   ",".join(map(str, ranks)), time.strftime("%Y-%m-%d"), args.rounds, elapsed))
        f.write("\n".join(machine()) + "\n\n")
        f.write("Scene: `csgtrace gen spheres --count 50 --occupancy 0.5 --seed 1`; ranks: "
                "master + workers under `%s`. Medians (min-max) over the rounds. Speed-ups are "
                "the serial render's (same size, tile, format) over this one's: the frame "
                "(wall_s) and the tile phase (tile_phase_s); efficiency divides by the "
                "workers. busy: the workers' busy share of their tile phase. tail: write_s "
                "/ wall_s, the write after the last tile.\n\n" % args.mpirun)
        for size in sizes:
            for fmt in formats:
                same_all = identical.get((size, fmt), True)
                f.write("## %d x %d, %s (every image the serial one, bit for bit: %s)\n\n"
                        % (size, size, fmt.upper(), "yes" if same_all else "NO"))
                f.write("| mode | ranks | tile | wall s | frame speed-up | frame eff. | tile "
                        "phase s | tile speed-up | tile eff. | busy | write tail |\n"
                        "|---|---:|---:|---|---:|---:|---|---:|---:|---:|---:|\n")
                for tile in tiles:
                    serial = runs[(size, "serial", 1, tile, fmt)]
                    sw = statistics.median(s["wall_s"] for s in serial)
                    stp = statistics.median(s["tile_phase_s"] for s in serial)
                    for c in [c for c in configs if c[0] == size and c[3] == tile and c[4] == fmt]:
                        rs = runs[c]
                        wall = statistics.median(s["wall_s"] for s in rs)
                        tp = statistics.median(s["tile_phase_s"] for s in rs)
                        workers = max(1, c[2] - 1) if c[1] != "serial" else 1
                        f.write("| %s | %d | %d | %s | %.2f | %.0f %% | %s | %.2f | %.0f %% | "
                                "%.0f %% | %.1f %% |\n"
                                % (c[1], c[2], tile, cell([s["wall_s"] for s in rs]), sw / wall,
                                   100 * sw / wall / workers,
                                   cell([s["tile_phase_s"] for s in rs]), stp / tp,
                                   100 * stp / tp / workers,
                                   100 * statistics.median(s["busy_fraction"] for s in rs),
                                   100 * statistics.median(s["write_s"] / s["wall_s"]
                                                           for s in rs)))
                f.write("\n")
    print("node.py: %s written (%.0f s)" % (args.report, elapsed))


if __name__ == "__main__":
    main()
