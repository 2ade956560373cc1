#!/usr/bin/env python3
"""costmap.py [--column wire_bytes] OUT STATS_JSON TILE_LOG [STATS_JSON TILE_LOG ...]
— tile logs of real renders of one configuration, reduced to the cost map
the simulated build reads (sim/tile_sim.h).

--column wire_bytes: the map's first column is each tile's compressed pixels
instead (a render with --compress on): the bytes a simulated part carries
($CSGSIM_WIRE_BYTES, sim/tile_run.c).  They depend on the image only, not
on the machine or the mode.

A cell's cost is the tile's "cpu_s", the CPU time of the worker's thread
(its "seconds", wall time, in logs older than that field): the work
itself.  Wall time also holds the time the worker's core spent on other
ranks, and the simulation shares a host's cores among its ranks itself;
where ranks outnumber the cores (bench/sim/validate.sh up to 7 workers on
2 cores), wall seconds would count that sharing twice.

Several renders: each cell gets its smallest seconds and the pass its
smallest duration.  On a shared machine a tile's seconds include any time
the worker was preempted (a few ms, against a mean of 0.2 ms: seen here),
and one such outlier, scaled up to a 4096x4096 tile, becomes the tail of
every simulation; the minimum of a few renders drops it.

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


def reduce(pairs, column=None):
    """Per cell (seconds, hits, estimate) and pass_s: the minimum over renders
    (column: that field of the log instead of the seconds)."""
    cells, pass_s, first = None, None, None
    for stats_path, log_path in pairs:
        stats, items = load(log_path, stats_path)
        key = (stats["width"], stats["height"], stats["tile"], stats["mode"])
        if first and key != first:
            sys.exit("costmap.py: the renders differ in size, tile or mode")
        first = key
        count = ((key[0] + key[2] - 1) // key[2]) * ((key[1] + key[2] - 1) // key[2])
        if sorted(items) != list(range(count)):
            sys.exit("costmap.py: a log does not cover every tile once")
        got = [(0.0 if it["skipped"] else float(it[column]) if column else
                float(it.get("cpu_s", it["seconds"])), int(it["hits"]),
                float(it["estimate"] or 0.0)) for it in (items[i] for i in range(count))]
        cells = got if cells is None else [(min(a[0], b[0]), a[1], a[2]) for a, b in zip(cells, got)]
        p = float(stats.get("pass_s") or 0) if key[3] == "hetero" else 0.0
        pass_s = p if pass_s is None else min(pass_s, p)
    return first, cells, pass_s


def main():
    args, column = sys.argv[1:], None
    if args[:1] == ["--column"]:
        if len(args) < 2 or args[1] != "wire_bytes":
            sys.exit("costmap.py: --column takes wire_bytes")
        column, args = args[1], args[2:]
    if len(args) < 3 or len(args) % 2 == 0:
        sys.exit(__doc__)
    pairs = list(zip(args[1::2], args[2::2]))
    (width, height, tile, _), cells, pass_s = reduce(pairs, column)
    if column and not any(c[0] for c in cells):
        sys.exit("costmap.py: no compressed bytes in the log (render with --compress on)")
    with open(args[0], "w") as out:
        out.write(f"csgsim-costs 1 {width} {height} {tile} {pass_s:.9g}\n")
        for sec, hits, est in cells:
            out.write(f"{sec:.9g} {hits} {est:.9g}\n")


if __name__ == "__main__":
    main()
