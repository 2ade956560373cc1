#!/usr/bin/env python3
"""collect.py — the bookkeeping of the benchmark suite (stdlib only).

Subcommands (bench/run.sh and bench/vs_povray.sh call them):

  append CSV STATS.json [key=value ...]
      One row per run: the given metadata, then every field of the stats JSON
      flattened (rays.primary -> rays_primary, workers[0].busy_s ->
      workers_0_busy_s), then time_s = wall_s - compile_s, the compared figure
      (the kernel build is reported apart, never inside it).  A new column
      rewrites the file with the union of the headers.
  append-kv CSV key=value ...
      The same without a JSON file (POV-Ray runs).
  copy SRC DST EXPERIMENT "COUNTS" "OCCS"
      Appends SRC's rows with those counts and occupancies to DST (the 384
      point of Figure 3 reuses the runs of Figure 1).
  idiff FILE
      Parses `idiff` output into key=value words (mean_err rms_err psnr
      max_err px_over_pct), printed on one line.
  report RESULTS_DIR TEMPLATE OUT.md
      Medians per configuration and mode, the heterogeneous advantage
      (homo - hetero) / homo in % from the medians, the averages of the
      paper's Figures 2 and 3, the wide .dat tables the gnuplot scripts read,
      and RESULTS.md filled from TEMPLATE ({{name}} placeholders).

Invariant: the advantage of a configuration is computed from the medians of
its own repeats, homo and hetero of the same scene, size, tile and ranks; an
average over configurations averages those advantages (as the paper does),
never the raw times.
"""
import csv
import json
import os
import re
import statistics
import sys

# A configuration: what must match between the homo and hetero runs compared.
CONFIG_KEYS = ("count", "occ_target", "seed", "width", "height", "tile", "ranks")

PAPER = {
    "objects": "grew from 10% to 23% with 10 -> 50 objects (Figure 1)",
    "occupancy": "fell from 17% to 12% with occupancy 20% -> 80% (Figure 2)",
    "size": "grew from 11% to 17% with image size 192 -> 384 (Figure 3)",
}
PAPER_POINTS = {  # the endpoints the paper states, for the plots
    "objects": [(10, 10.0), (50, 23.0)],
    "occupancy": [(20, 17.0), (80, 12.0)],
    "size": [(192, 11.0), (384, 17.0)],
}


# ---- rows ----------------------------------------------------------------------

def flatten(prefix, value, out):
    """Flattens nested dicts and lists into out[prefix_key] = scalar."""
    if isinstance(value, dict):
        for k, v in value.items():
            flatten(f"{prefix}_{k}" if prefix else k, v, out)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            flatten(f"{prefix}_{i}", v, out)
    else:
        out[prefix] = "" if value is None else value


def parse_kv(words):
    row = {}
    for w in words:
        if "=" not in w:
            sys.exit(f"collect.py: expected key=value, got '{w}'")
        k, v = w.split("=", 1)
        row[k] = v
    return row


def read_text(path):
    with open(path, errors="replace") as f:
        return f.read()


def read_csv(path):
    if not os.path.exists(path):
        return [], []
    with open(path, newline="") as f:
        r = csv.DictReader(f)
        return list(r.fieldnames or []), list(r)


def write_csv(path, header, rows):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=header, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: row.get(k, "") for k in header})
    os.replace(tmp, path)


def append_row(path, row):
    header, rows = read_csv(path)
    new = [k for k in row if k not in header]
    if new or not header:
        write_csv(path, header + new, rows + [row])
    else:
        with open(path, "a", newline="") as f:
            csv.DictWriter(f, fieldnames=header, extrasaction="ignore").writerow(
                {k: row.get(k, "") for k in header})


def cmd_append(args):
    path, stats_path = args[0], args[1]
    row = parse_kv(args[2:])
    with open(stats_path) as f:
        stats = json.load(f)
    flat = {}
    flatten("", stats, flat)
    row.update(flat)
    row["time_s"] = "%.6f" % (float(flat["wall_s"]) - float(flat.get("compile_s") or 0))
    append_row(path, row)


def cmd_append_kv(args):
    append_row(args[0], parse_kv(args[1:]))


def cmd_copy(args):
    """copy SRC DST EXPERIMENT "COUNTS" "OCCS": appends SRC's rows with those
    counts and occupancy targets to DST, relabelled."""
    src, dst, exp, counts, occs = args[0], args[1], args[2], args[3].split(), args[4].split()
    for r in read_csv(src)[1]:
        if r.get("count") in counts and r.get("occ_target") in occs:
            r["experiment"] = exp
            append_row(dst, r)


def cmd_idiff(args):
    text = read_text(args[0])
    pats = {
        "mean_err": r"Mean error\s*=\s*([-+0-9.eE]+|inf|nan)",
        "rms_err": r"RMS error\s*=\s*([-+0-9.eE]+|inf|nan)",
        "psnr": r"Peak SNR\s*=\s*([-+0-9.eE]+|inf|nan)",
        "max_err": r"Max error\s*=\s*([-+0-9.eE]+|inf|nan)",
        "px_over_pct": r"\(([-+0-9.eE]+)%\) over",
    }
    out = []
    for k, p in pats.items():
        m = re.search(p, text)
        val = m.group(1) if m else ""
        if k == "px_over_pct" and not m and "PASS" in text:
            val = "0"
        out.append(f"{k}={val}")
    print(" ".join(out))


# ---- aggregation -----------------------------------------------------------------

def num(row, key, default=float("nan")):
    try:
        return float(row[key])
    except (KeyError, TypeError, ValueError):
        return default


def config_of(row):
    return tuple(row.get(k, "") for k in CONFIG_KEYS)


def median_of(rows, key):
    vals = [num(r, key) for r in rows]
    vals = [v for v in vals if v == v]
    return statistics.median(vals) if vals else float("nan")


def derive(r):
    """other_s: the part of wall_s no phase names (in hetero mode mostly the
    OpenCL platform, context and buffer set-up around the kernel build)."""
    parts = [num(r, k, 0.0) for k in ("setup_s", "compile_s", "primary_s", "secondary_s",
                                      "write_s")]
    r["other_s"] = num(r, "wall_s") - sum(parts)
    return r


def summarize(rows):
    """One dict per configuration: medians per mode and the advantage."""
    groups = {}
    for r in map(derive, rows):
        groups.setdefault(config_of(r), {}).setdefault(r.get("mode", ""), []).append(r)
    out = []
    for cfg, by_mode in groups.items():
        s = dict(zip(CONFIG_KEYS, cfg))
        any_rows = next(iter(by_mode.values()))
        s["occupancy"] = median_of(any_rows, "occupancy")
        for mode in ("homo", "hetero"):
            rs = by_mode.get(mode, [])
            s[f"{mode}_n"] = len(rs)
            for key in ("time_s", "primary_s", "secondary_s", "compile_s", "other_s",
                        "write_s", "setup_s", "tiles_sent",
                        "tiles_total", "bytes_sent", "bytes_received", "rays_total"):
                s[f"{mode}_{key}"] = median_of(rs, key)
            if rs:
                spread = [num(r, "time_s") for r in rs]
                s[f"{mode}_min_s"], s[f"{mode}_max_s"] = min(spread), max(spread)
        h, g = s.get("homo_time_s", float("nan")), s.get("hetero_time_s", float("nan"))
        s["advantage_pct"] = 100.0 * (h - g) / h if h == h and g == g and h > 0 else float("nan")
        # The same from the fastest repeat of each mode: on a shared machine
        # the minimum is the least disturbed figure, a cross-check.
        h, g = s.get("homo_min_s", float("nan")), s.get("hetero_min_s", float("nan"))
        s["advantage_min_pct"] = 100.0 * (h - g) / h if h == h and g == g and h > 0 else float("nan")
        out.append(s)
    return out


def mean(vals):
    vals = [v for v in vals if v == v]
    return sum(vals) / len(vals) if vals else float("nan")


def key_num(v):
    try:
        return float(v)
    except ValueError:
        return float("inf")


def fmt(v, spec=".1f"):
    if isinstance(v, float):
        return "n/a" if v != v else format(v, spec)
    return str(v)


def group_mean(summary, by, field="advantage_pct"):
    """{value of `by`: mean of field over the configurations with it}."""
    acc = {}
    for s in summary:
        acc.setdefault(s[by], []).append(s[field])
    return {k: mean(v) for k, v in sorted(acc.items(), key=lambda kv: key_num(kv[0]))}


def write_dat(path, header, rows):
    with open(path, "w") as f:
        f.write(" ".join(header) + "\n")  # the column heads (gnuplot: columnhead)
        for row in rows:
            f.write(" ".join(fmt(v, ".6g") if isinstance(v, float) else str(v)
                             for v in row).replace("n/a", "NaN") + "\n")


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def phase_rows(summary, label_keys):
    """Markdown rows: medians of both modes' phases per configuration."""
    rows = []
    for s in sorted(summary, key=lambda s: tuple(key_num(s[k]) for k in label_keys)):
        skipped = s["hetero_tiles_total"] - s["hetero_tiles_sent"]
        rows.append([*(str(s[k]) for k in label_keys),
                     fmt(100 * s["occupancy"]),
                     fmt(s["homo_time_s"], ".3f"), fmt(s["hetero_time_s"], ".3f"),
                     fmt(s["hetero_primary_s"], ".3f"),
                     fmt(s["hetero_other_s"], ".3f"),
                     fmt(s["homo_secondary_s"], ".3f"), fmt(s["hetero_secondary_s"], ".3f"),
                     f"{fmt(skipped, '.0f')}/{fmt(s['hetero_tiles_total'], '.0f')}",
                     fmt(s["hetero_bytes_sent"] / 1e6, ".2f"),
                     fmt(s["hetero_compile_s"], ".3f"),
                     fmt(s["advantage_pct"]), fmt(s["advantage_min_pct"])])
    return rows


PHASE_HEADER = ["occ. %", "homo s", "hetero s", "SIMD primary s", "hetero other s",
                "homo sec. s", "hetero sec. s", "tiles skipped", "hetero MB sent",
                "compile s (excl.)", "adv. %", "adv. % (fastest)"]


def decompose(summary, by):
    """[(value, [homo s, saved %, primary %, other %, skipped %, adv %])]: per
    configuration, saved = homo sec. - hetero sec. (the primary rays and the
    empty tiles the workers no longer trace, net of the hit records they now
    receive), primary = the SIMD pass, other = its set-up; all in % of the homo
    time, then averaged over the configurations with that value of `by`."""
    acc = {}
    for s in summary:
        h = s["homo_time_s"]
        if not h == h or h <= 0:
            continue
        acc.setdefault(s[by], []).append([
            h,
            100 * (s["homo_secondary_s"] - s["hetero_secondary_s"]) / h,
            100 * s["hetero_primary_s"] / h,
            100 * s["hetero_other_s"] / h,
            100 * (s["hetero_tiles_total"] - s["hetero_tiles_sent"]) / s["hetero_tiles_total"],
            s["advantage_pct"]])
    return [(k, [mean(col) for col in zip(*v)])
            for k, v in sorted(acc.items(), key=lambda kv: key_num(kv[0]))]


def run_info_line(rows):
    if not rows:
        return "no runs"
    r = rows[0]
    dates = sorted(x.get("date", "") for x in rows)
    return (f"{len(rows)} runs, {dates[0]} .. {dates[-1]}, commit `{r.get('commit', '?')}`, "
            f"CPU {r.get('cpu', '?')} ({r.get('cores', '?')} cores), {r.get('ranks', '?')} ranks, "
            f"suite `{r.get('suite', '?')}`")


def cmd_report(args):
    res, template_path, out_md = args
    fill = {}

    def load(name):
        return read_csv(os.path.join(res, name + ".csv"))[1]

    # Figure 1: advantage vs objects, one line per occupancy.
    objects = load("objects")
    s_obj = summarize(objects)
    write_csv(os.path.join(res, "objects_summary.csv"), list(s_obj[0].keys()) if s_obj else [],
              s_obj)
    occs = sorted({s["occ_target"] for s in s_obj}, key=key_num)
    counts = sorted({s["count"] for s in s_obj}, key=key_num)
    table = []
    for c in counts:
        row = [c]
        for o in occs:
            row.append(mean([s["advantage_pct"] for s in s_obj
                             if s["count"] == c and s["occ_target"] == o]))
        table.append(row)
    write_dat(os.path.join(res, "objects.dat"), ["count"] + [f"occ{o}" for o in occs], table)
    min_mean = group_mean(s_obj, "count", "advantage_min_pct")
    fill["objects_table"] = md_table(
        ["objects"] + [f"adv. % at occ. {o}%" for o in occs] + ["mean", "mean (fastest of R)"],
        [[str(r[0])] + [fmt(v) for v in r[1:]] + [fmt(mean(r[1:])), fmt(min_mean[r[0]])]
         for r in table])
    fill["objects_run"] = run_info_line(objects)
    fill["objects_phases"] = md_table(["objects", "occ. target %"] + PHASE_HEADER,
                                      phase_rows(s_obj, ["count", "occ_target"]))

    # Figure 2: occupancy, averaged over objects (the same runs).
    occ_mean = group_mean(s_obj, "occ_target")
    write_dat(os.path.join(res, "occupancy.dat"), ["occ", "adv"],
              [[k, v] for k, v in occ_mean.items()])
    occ_min = group_mean(s_obj, "occ_target", "advantage_min_pct")
    fill["occupancy_table"] = md_table(["occupancy target %", "measured %", "mean adv. %",
                                        "mean adv. % (fastest of R)"],
                                       [[k, fmt(100 * mean([s["occupancy"] for s in s_obj
                                                           if s["occ_target"] == k])), fmt(v),
                                         fmt(occ_min[k])]
                                        for k, v in occ_mean.items()])

    # Figure 3: image size, averaged over objects and occupancies.
    sizes = load("size")
    s_size = summarize(sizes)
    size_mean = group_mean(s_size, "width")
    write_dat(os.path.join(res, "size.dat"), ["size", "adv"], [[k, v] for k, v in size_mean.items()])
    size_min = group_mean(s_size, "width", "advantage_min_pct")
    fill["size_table"] = md_table(["size", "configurations", "mean adv. %",
                                   "mean adv. % (fastest of R)"],
                                  [[f"{k}x{k}", str(sum(1 for s in s_size if s['width'] == k)),
                                    fmt(v), fmt(size_min[k])] for k, v in size_mean.items()])
    fill["size_run"] = run_info_line(sizes)
    fill["size_phases"] = md_table(["size", "objects", "occ. target %"] + PHASE_HEADER,
                                   phase_rows(s_size, ["width", "count", "occ_target"]))

    # Headline next to the paper.
    def ends(d):
        ks = list(d.keys())
        return (fmt(d[ks[0]]), fmt(d[ks[-1]]), ks[0], ks[-1]) if ks else ("n/a",) * 4

    head = []
    for label, summ, by, unit in (("objects", s_obj, "count", " objects"),
                                  ("occupancy", s_obj, "occ_target", "%"),
                                  ("size", s_size, "width", " px")):
        a, b, k0, k1 = ends(group_mean(summ, by))
        am, bm, _, _ = ends(group_mean(summ, by, "advantage_min_pct"))
        head.append([label, PAPER[label], f"{a}% -> {b}% with {k0}{unit} -> {k1}{unit}",
                     f"{am}% -> {bm}%"])
    fill["headline"] = md_table(["experiment", "paper (1990s)", "ours (medians of R)",
                                 "ours (fastest of R)"], head)

    # Why ours differ: the advantage split into what the worker phase saves and
    # what the SIMD pass costs, as % of the homo time (means over configurations).
    why = []
    for label, summ, by in (("objects", s_obj, "count"), ("occupancy %", s_obj, "occ_target"),
                            ("size", s_size, "width")):
        for k, g in decompose(summ, by):
            why.append([label, str(k), fmt(g[0], ".3f")] + [fmt(v) for v in g[1:]])
    fill["why_table"] = md_table(
        ["sweep", "value", "homo s", "worker phase saved %", "SIMD primary %",
         "hetero other %", "tiles skipped %", "adv. %"], why)

    # Beyond the paper: one table and .dat per sweep.
    for name, by, label in (("big_objects", "count", "objects"),
                            ("big_size", "width", "size"),
                            ("occ_sweep", "occ_target", "occupancy target %")):
        rows = load(name)
        s = summarize(rows)
        if s:
            write_csv(os.path.join(res, name + "_summary.csv"), list(s[0].keys()), s)
        g = group_mean(s, by)
        write_dat(os.path.join(res, name + ".dat"), [by, "adv"], [[k, v] for k, v in g.items()])
        fill[name + "_run"] = run_info_line(rows)
        fill[name + "_phases"] = md_table([label] + PHASE_HEADER, phase_rows(s, [by]))

    # Tile sweep: median time per mode and tile, the best tile per mode.
    tiles = load("tile")
    s_tile = summarize(tiles)
    if s_tile:
        write_csv(os.path.join(res, "tile_summary.csv"), list(s_tile[0].keys()), s_tile)
    s_tile.sort(key=lambda s: key_num(s["tile"]))
    write_dat(os.path.join(res, "tile.dat"), ["tile", "homo_s", "hetero_s", "adv"],
              [[s["tile"], s["homo_time_s"], s["hetero_time_s"], s["advantage_pct"]]
               for s in s_tile])
    best = []
    for mode in ("homo", "hetero"):
        cand = [s for s in s_tile if s[f"{mode}_time_s"] == s[f"{mode}_time_s"]]
        if cand:
            b = min(cand, key=lambda s: s[f"{mode}_time_s"])
            best.append([mode, str(b["tile"]), fmt(b[f"{mode}_time_s"], ".3f")])
    fill["tile_best"] = md_table(["mode", "best tile", "median s"], best)
    fill["tile_run"] = run_info_line(tiles)
    fill["tile_phases"] = md_table(["tile"] + PHASE_HEADER, phase_rows(s_tile, ["tile"]))

    # POV-Ray comparison (bench/vs_povray.sh).
    pov = load("vs_povray")
    fill["povray_run"] = run_info_line(pov)
    fill["povray_table"] = povray_table(pov)

    info_path = os.path.join(res, "run_info.json")
    info = json.loads(read_text(info_path)) if os.path.exists(info_path) else {}
    fill["suite_info"] = (
        f"suite `{info.get('suite', '?')}`, started {info.get('start', '?')}, "
        f"took {fmt(float(info.get('elapsed_s', 'nan')), '.0f')} s, commit `{info.get('commit', '?')}`, "
        f"CPU {info.get('cpu', '?')} ({info.get('cores', '?')} cores), {info.get('ranks', '?')} ranks, "
        f"{info.get('repeats', '?')} repeats per mode, load average at start "
        f"{info.get('load_start', '?')}, at end {info.get('load_end', '?')}")

    text = read_text(template_path)
    missing = set(re.findall(r"{{(\w+)}}", text)) - set(fill)
    for k in missing:
        fill[k] = "(not run)"
    text = re.sub(r"{{(\w+)}}", lambda m: fill[m.group(1)], text)
    with open(out_md, "w") as f:
        f.write(text)


def povray_table(rows):
    """The trace-to-trace table of bench/vs_povray.sh (bench/speed_report.py)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import speed_report
    return speed_report.povray_section(rows)


def main(argv):
    cmds = {"append": cmd_append, "append-kv": cmd_append_kv, "copy": cmd_copy, "idiff": cmd_idiff,
            "report": cmd_report}
    if len(argv) < 2 or argv[1] not in cmds:
        sys.exit("usage: collect.py append|append-kv|copy|idiff|report ...  (see the header)")
    cmds[argv[1]](argv[2:])


if __name__ == "__main__":
    main(sys.argv)
