#!/usr/bin/env python3
"""costmap.py TILE_LOG STATS_JSON OUT — a tile log of a real render, reduced
to the cost map the simulated build reads (workers/tile_sim.h).

The log must come from a render with whole tiles only (any schedule but
tail): every tile is one cell, its seconds / hits / estimate the cell's.
Skipped tiles (hetero, no hit) are cells of zero.  pass_s is the stats'
pass_s in hetero (the OpenCL pass, pipelined) and 0 in homo.
"""
import json
import sys


def load(log_path, stats_path):
    stats = json.load(open(stats_path))
    cells = {}
    for line in open(log_path):
        it = json.loads(line)
        if it["piece"] != 0:
            sys.exit("costmap.py: a split tile in the log (record without --schedule tail)")
        cells[it["tile"]] = it
    return stats, cells


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    stats, cells = load(sys.argv[1], sys.argv[2])
    width, height, tile = int(stats["width"]), int(stats["height"]), int(stats["tile"])
    count = ((width + tile - 1) // tile) * ((height + tile - 1) // tile)
    if sorted(cells) != list(range(count)):
        sys.exit("costmap.py: the log does not cover every tile once")
    pass_s = float(stats.get("pass_s") or 0) if stats["mode"] == "hetero" else 0.0
    with open(sys.argv[3], "w") as out:
        out.write(f"csgsim-costs 1 {width} {height} {tile} {pass_s:.9g}\n")
        for i in range(count):
            it = cells[i]
            est = it["estimate"] if it["estimate"] is not None else 0.0
            sec = 0.0 if it["skipped"] else float(it["seconds"])
            out.write(f"{sec:.9g} {int(it['hits'])} {float(est):.9g}\n")


if __name__ == "__main__":
    main()
