#!/usr/bin/env python3
"""node_validate.py — the simulator against the 16-core node's runs
(../shared/node/h200-2026-11-28/, issue 35 item 4), then the same
configurations with today's runtime.

Each case is a configuration the node ran (master + 15 workers,
2048x2048 or 4096x4096, `gen spheres --count 50 --occupancy 0.5 --seed 1`)
with its measured runs.  The node ran the build of 2026-11-27 (294e950),
so the cases are simulated with `--runtime legacy` (a message received
whole before the next; no progress while a worker computes) on
bench/sim/node.xml, with Open MPI's shared-memory protocol modelled as that
node had it: eager limit 4096 bytes, larger messages moving only when the
sender calls MPI again (no cross-memory attach there: its README's cma/);
the cases run under other MCA settings say so.  The cost maps are the
node's own tile logs (scaling/homo16.jsonl, hetero16.jsonl; hetero's
whole tiles, the fill, cost what homo's do), scaled to 4096x4096 where
the case is that size.  Hetero's pass starts after the device's set-up
(the run's cl_setup_s), as the fill did there.

Prints a Markdown table: per case the measured tile phases, the simulated
one and its difference from their median; the frame, measured and
composed (the run's setup and write, which are not simulated, plus the
simulated tile phase); and the same case simulated with today's runtime
(`--runtime current`).  Writes the table to --report (default
bench/results-scale/node-validate.md).

Usage: bench/sim/node_validate.py [--node DIR] [--report FILE]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NODE = os.path.join(ROOT, "..", "shared", "node", "h200-2026-11-28")

# name, size, mode, simulate.sh arguments, the measured runs' stats
# (files under NODE; "cmp:FILE" is a compare's homo rounds)
CASES = [
    ("homo, tile 32", 2048, "homo", ["--tile", "32"],
     ["scaling/homo16.json", "scaling/homo16_b.json", "stall/h16_png.json"]),
    ("homo, tile 64", 2048, "homo", ["--tile", "64"],
     ["scaling/homo16_t64.json", "stall/h16_t64.json", "cma/t64_default.json",
      "cma/t64_default_b.json", "cma/t64_none.json"]),
    ("homo, tile 64, eager limit 65536", 2048, "homo", ["--tile", "64", "--eager-bytes", "65536"],
     ["stall/h16_t64_eager.json"]),
    ("homo, tile 64, cross-memory attach", 2048, "homo",
     ["--tile", "64", "--sender-progress", "no"], ["cma/t64_cma.json"]),
    ("homo, tile 32, --batch 4", 2048, "homo", ["--tile", "32", "--batch", "4"],
     ["scaling/homo16_batch4.json"]),
    ("homo, tile 32, float results (compare)", 2048, "homo",
     ["--tile", "32", "--pixels", "float"], ["cmp:stall/cmp16.json"]),
    ("homo, tile 32, float results, eager limit 65536", 2048, "homo",
     ["--tile", "32", "--pixels", "float", "--eager-bytes", "65536"],
     ["cmp:stall/cmp16_eager.json"]),
    ("hetero, tile 32", 2048, "hetero", ["--tile", "32"],
     ["scaling/hetero16.json", "scaling/hetero16_b.json", "stall/x16_png.json"]),
    ("homo, tile 32, 4096x4096", 4096, "homo", ["--tile", "32"],
     ["stall/h16_4k_png.json", "stall/h16_4k_png_b.json"]),
    ("hetero, tile 32, 4096x4096", 4096, "hetero", ["--tile", "32"],
     ["stall/x16_4k_png.json", "stall/x16_4k_png_b.json"]),
]


def runs_of(node, spec):
    """The measured runs' stats objects."""
    if spec.startswith("cmp:"):
        return json.load(open(os.path.join(node, spec[4:])))["homo"]
    return [json.load(open(os.path.join(node, spec)))]


def simulate(scene, maps, size, mode, args, runtime, pass_delay, work):
    out = os.path.join(work, "point.json")
    cmd = [os.path.join(ROOT, "bench", "simulate.sh"), scene, "--workers", "15", "--mode", mode,
           "--network", "node", "--size", f"{size}x{size}", "--map", maps[mode],
           "--runtime", runtime, "--stats", out] + args
    if mode == "hetero":
        cmd += ["--fill-map", maps["homo"], "--pass-delay", f"{pass_delay:.6f}"]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.load(open(out))


def pct(sim, real):
    return f"{100 * (sim - real) / real:+.1f} %"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--node", default=NODE)
    ap.add_argument("--report",
                    default=os.path.join(ROOT, "bench", "results-scale", "node-validate.md"))
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="node-validate-")
    csgtrace = os.path.join(ROOT, "build", "csgtrace")
    scene = os.path.join(work, "s50.pov")
    subprocess.run([csgtrace, "gen", "spheres", "--count", "50", "--occupancy", "0.5", "--seed",
                    "1", "--width", "2048", "--height", "2048", "-o", scene], check=True,
                   capture_output=True)
    maps = {}
    for mode in ("homo", "hetero"):
        maps[mode] = os.path.join(work, f"{mode}16.costs")
        base = os.path.join(a.node, "scaling", f"{mode}16")
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "sim", "costmap.py"),
                        maps[mode], base + ".json", base + ".jsonl"], check=True)
    rows = ["| case | measured tile phase (s) | simulated | difference | measured frame "
            "(s) | composed frame | difference | workers busy, measured / simulated | "
            "today's runtime, simulated tile phase | busy |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name, size, mode, args, specs in CASES:
        runs = [r for s in specs for r in runs_of(a.node, s)]
        phases = [r["tile_phase_s"] for r in runs]
        frames = [r["wall_s"] for r in runs]
        busy = statistics.median(r["busy_fraction"] for r in runs)
        delay = statistics.median(r["cl_setup_s"] for r in runs)
        old = simulate(scene, maps, size, mode, args, "legacy", delay, work)
        new = simulate(scene, maps, size, mode, args, "current", delay, work)
        phase, frame = statistics.median(phases), statistics.median(frames)
        composed = statistics.median(r["wall_s"] - r["tile_phase_s"] for r in runs) + \
            old["makespan_s"]
        # the simulated workers' busy share: their items' seconds over the tile phase
        sim_busy = old["work_s"] / (15 * old["makespan_s"])
        new_busy = new["work_s"] / (15 * new["makespan_s"])
        rows.append(
            f"| {name} | {', '.join(f'{p:.3f}' for p in phases)} | {old['makespan_s']:.3f} | "
            f"{pct(old['makespan_s'], phase)} | {frame:.3f} | {composed:.3f} | "
            f"{pct(composed, frame)} | {100 * busy:.0f} / {100 * sim_busy:.0f} % | "
            f"{new['makespan_s']:.3f} | {100 * new_busy:.0f} % |")
        print(rows[-1], flush=True)
    os.makedirs(os.path.dirname(a.report), exist_ok=True)
    with open(a.report, "w") as f:
        f.write("# The simulator against the node (bench/sim/node_validate.py)\n\n")
        f.write("\n".join(rows) + "\n")
    subprocess.run(["rm", "-rf", work])


if __name__ == "__main__":
    main()
