#!/usr/bin/env python3
"""collect.py — the bookkeeping of the benchmark suite (stdlib only).

Subcommands (bench/run.sh and bench/vs_povray.sh call them):

  append CSV STATS.json [key=value ...]
      One row per run: the given metadata, then every field of the stats JSON
      flattened (rays.primary -> rays_primary, workers[0].busy_s ->
      workers_0_busy_s), then time_s = wall_s - compile_s - cl_setup_s, the
      compared figure (the kernel build and the OpenCL set-up are reported
      apart, never inside it).  A new column rewrites the file with the union
      of the headers.
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
CONFIG_KEYS = ("count", "occ_target", "seed", "width", "height", "tile", "ranks", "sched_arg")
# A round: the homo and the hetero render compared with each other.
ROUND_KEYS = ("job", "repeat")
# The phases of a render (they add up to wall_s, host/stats.h).
PHASES = ("setup_s", "cl_setup_s", "compile_s", "primary_s", "pipelined_s", "secondary_s",
          "write_s")

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
    row["time_s"] = "%.6f" % (float(flat["wall_s"]) - float(flat.get("compile_s") or 0) -
                               float(flat.get("cl_setup_s") or 0))
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
    """phase_gap_s: wall_s less the sum of the phases (0 to rounding since the
    phases are consecutive; a check); other_s: the same, kept for old CSVs
    without cl_setup_s / pipelined_s, where it was the OpenCL set-up."""
    gap = num(r, "wall_s") - sum(num(r, k, 0.0) for k in PHASES)
    r["phase_gap_s"] = gap
    r["other_s"] = gap + num(r, "cl_setup_s", 0.0)
    r["hetero_tile_s"] = num(r, "pipelined_s", 0.0) + num(r, "secondary_s", 0.0)
    return r


def quantile(vals, q):
    """Linear interpolation between order statistics (numpy's default)."""
    vals = sorted(v for v in vals if v == v)
    if not vals:
        return float("nan")
    pos = q * (len(vals) - 1)
    lo = int(pos)
    hi = min(lo + 1, len(vals) - 1)
    return vals[lo] + (vals[hi] - vals[lo]) * (pos - lo)


def advantage(h, g):
    return 100.0 * (h - g) / h if h == h and g == g and h > 0 else float("nan")


def rounds_of(by_mode):
    """[(job, homo row, hetero row)] for every round with both renders."""
    keyed = {}
    for mode in ("homo", "hetero"):
        for r in by_mode.get(mode, []):
            key = tuple(r.get(k, "") for k in ROUND_KEYS)
            if "" not in key:
                keyed.setdefault(key, {})[mode] = r
    return [(k[0], v["homo"], v["hetero"]) for k, v in sorted(keyed.items())
            if len(v) == 2]


def paired(s, by_mode):
    """The per-round advantages: median, min .. max, the quartiles, and the
    range of the per-job medians (what one job alone could have said)."""
    rounds = rounds_of(by_mode)
    adv = [advantage(num(h, "time_s"), num(g, "time_s")) for _, h, g in rounds]
    jobs = {}
    for (job, _, _), a in zip(rounds, adv):
        jobs.setdefault(job, []).append(a)
    job_medians = [statistics.median(v) for v in jobs.values()]
    s["rounds"] = len(adv)
    s["jobs"] = len(jobs)
    s["adv_paired_pct"] = statistics.median(adv) if adv else float("nan")
    s["adv_lo_pct"] = min(adv) if adv else float("nan")
    s["adv_hi_pct"] = max(adv) if adv else float("nan")
    s["adv_q1_pct"], s["adv_q3_pct"] = quantile(adv, 0.25), quantile(adv, 0.75)
    s["adv_job_lo_pct"] = min(job_medians) if job_medians else float("nan")
    s["adv_job_hi_pct"] = max(job_medians) if job_medians else float("nan")
    # Slower beyond the spread: hetero lost every round.
    s["hetero_slower"] = bool(adv) and max(adv) < 0


MEDIAN_KEYS = ("time_s", "primary_s", "secondary_s", "compile_s", "cl_setup_s", "other_s",
               "write_s", "setup_s", "pipelined_s", "pass_s", "tile_phase_s", "hetero_tile_s",
               "tail_s", "busy_fraction", "estimate_spearman", "phase_gap_s", "tiles_sent",
               "tiles_total", "items_sent", "bytes_sent", "bytes_received", "rays_total")


def summarize(rows):
    """One dict per configuration: medians per mode and the advantages."""
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
            s[f"{mode}_schedule"] = rs[0].get("schedule", "") if rs else ""
            for key in MEDIAN_KEYS:
                s[f"{mode}_{key}"] = median_of(rs, key)
            spread = [num(r, "time_s") for r in rs]
            s[f"{mode}_min_s"] = min(spread) if rs else float("nan")
            s[f"{mode}_max_s"] = max(spread) if rs else float("nan")
            s[f"{mode}_iqr_s"] = quantile(spread, 0.75) - quantile(spread, 0.25)
        s["advantage_pct"] = advantage(s["homo_time_s"], s["hetero_time_s"])
        # The same from the fastest run of each mode: on a shared machine
        # the minimum is the least disturbed figure, a cross-check.
        s["advantage_min_pct"] = advantage(s["homo_min_s"], s["hetero_min_s"])
        paired(s, by_mode)
        # The figure the tables and plots use: paired when there are rounds.
        s["adv_pct"] = s["adv_paired_pct"] if s["rounds"] else s["advantage_pct"]
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


def group_mean(summary, by, field="adv_pct"):
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


def spread_cell(s):
    """"median [lo .. hi]" of the paired advantages, or the medians' one."""
    if not s.get("rounds"):
        return fmt(s["advantage_pct"])
    mark = " (slower in every round)" if s["hetero_slower"] else ""
    return f"{fmt(s['adv_paired_pct'])} [{fmt(s['adv_lo_pct'])} .. {fmt(s['adv_hi_pct'])}]{mark}"


def phase_rows(summary, label_keys):
    """Markdown rows: medians of both modes' phases per configuration."""
    rows = []
    for s in sorted(summary, key=lambda s: tuple(key_num(s[k]) for k in label_keys)):
        skipped = s["hetero_tiles_total"] - s["hetero_tiles_sent"]
        rows.append([*(str(s[k]) for k in label_keys),
                     fmt(100 * s["occupancy"]),
                     fmt(s["homo_time_s"], ".3f"), fmt(s["hetero_time_s"], ".3f"),
                     spread_cell(s),
                     f"{fmt(s['adv_job_lo_pct'])} .. {fmt(s['adv_job_hi_pct'])}",
                     fmt(s["hetero_primary_s"], ".3f"), fmt(s["hetero_pipelined_s"], ".3f"),
                     fmt(s["hetero_pass_s"], ".3f"),
                     fmt(s["homo_secondary_s"], ".3f"), fmt(s["hetero_secondary_s"], ".3f"),
                     f"{fmt(100 * s['homo_busy_fraction'], '.0f')}/"
                     f"{fmt(100 * s['hetero_busy_fraction'], '.0f')}",
                     fmt(1000 * s["hetero_tail_s"], ".1f"),
                     fmt(s["hetero_estimate_spearman"], ".2f"),
                     f"{fmt(skipped, '.0f')}/{fmt(s['hetero_tiles_total'], '.0f')}",
                     fmt(s["hetero_bytes_sent"] / 1e6, ".2f")])
    return rows


PHASE_HEADER = ["occ. %", "homo s", "hetero s", "adv. % median [min .. max]",
                "per-job medians", "SIMD alone s", "pipelined s", "SIMD pass s",
                "homo tiles s", "hetero tiles after s", "busy % homo/hetero",
                "hetero tail ms", "rho", "tiles skipped", "hetero MB sent"]


def decompose(summary, by):
    """[(value, [homo s, saved %, SIMD alone %, hidden %, skipped %, adv %])]:
    per configuration, all in % of the homo time: saved = homo tile phase -
    hetero tile phase (pipelined + after: the primary rays and the empty tiles
    the workers no longer trace, net of the records they now receive and of
    the cores the overlapped pass takes from them); SIMD alone = the pass
    before any tile went out (nothing hides it); hidden = the share of the
    pass that ran under the tile phase; then averaged over the configurations
    with that value of `by`.  adv ~ saved - SIMD alone."""
    acc = {}
    for s in summary:
        h = s["homo_time_s"]
        if not h == h or h <= 0:
            continue
        pass_s = s["hetero_pass_s"]
        acc.setdefault(s[by], []).append([
            h,
            100 * (s["homo_secondary_s"] - s["hetero_hetero_tile_s"]) / h,
            100 * s["hetero_primary_s"] / h,
            100 * (1 - s["hetero_primary_s"] / pass_s) if pass_s and pass_s == pass_s else float("nan"),
            100 * (s["hetero_tiles_total"] - s["hetero_tiles_sent"]) / s["hetero_tiles_total"],
            s["adv_pct"]])
    return [(k, [mean(col) for col in zip(*v)])
            for k, v in sorted(acc.items(), key=lambda kv: key_num(kv[0]))]


def schedule_rows(summary):
    """One row per --schedule and mode: time, advantage, busy, tail, rho."""
    rows = []
    for s in sorted(summary, key=lambda s: s["sched_arg"]):
        for mode in ("homo", "hetero"):
            rows.append([s["sched_arg"], mode, s[f"{mode}_schedule"],
                         fmt(s[f"{mode}_time_s"], ".3f"),
                         f"{fmt(s[f'{mode}_min_s'], '.3f')} .. {fmt(s[f'{mode}_max_s'], '.3f')}",
                         fmt(100 * s[f"{mode}_busy_fraction"], ".1f"),
                         fmt(1000 * s[f"{mode}_tail_s"], ".2f"),
                         fmt(s[f"{mode}_estimate_spearman"], ".2f"),
                         fmt(s[f"{mode}_items_sent"], ".0f"),
                         spread_cell(s) if mode == "hetero" else ""])
    return md_table(["--schedule", "mode", "ran", "median s", "min .. max s", "busy %",
                     "tail ms", "rho", "items", "adv. % [min .. max]"], rows)


def checks_line(rows_by_exp):
    """How well the phases add up, how often hetero lost every round."""
    gaps, slower, configs = [], 0, 0
    for rows in rows_by_exp:
        gaps += [abs(derive(dict(r))["phase_gap_s"]) for r in rows if r.get("wall_s")]
        for s in summarize(rows):
            configs += 1
            slower += bool(s["hetero_slower"])
    worst = max(gaps) if gaps else float("nan")
    return (f"largest |wall_s - sum of the phases| over {len(gaps)} renders: "
            f"{fmt(1000 * worst, '.4f')} ms; configurations where hetero was slower in every "
            f"round: {slower} of {configs}")


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
            row.append(mean([s["adv_pct"] for s in s_obj
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
        width = mean([x["adv_hi_pct"] - x["adv_lo_pct"] for x in summ])
        head.append([label, PAPER[label], f"{a}% -> {b}% with {k0}{unit} -> {k1}{unit}",
                     f"{am}% -> {bm}%", fmt(width)])
    fill["headline"] = md_table(["experiment", "paper (1990s)", "ours (median of the rounds)",
                                 "ours (fastest of each mode)",
                                 "spread of the rounds (points, mean max - min)"], head)

    # Why ours differ: the advantage split into what the worker phase saves and
    # what the SIMD pass costs, as % of the homo time (means over configurations).
    why = []
    for label, summ, by in (("objects", s_obj, "count"), ("occupancy %", s_obj, "occ_target"),
                            ("size", s_size, "width")):
        for k, g in decompose(summ, by):
            why.append([label, str(k), fmt(g[0], ".3f")] + [fmt(v) for v in g[1:]])
    fill["why_table"] = md_table(
        ["sweep", "value", "homo s", "tile phase saved %", "SIMD alone %",
         "pass hidden %", "tiles skipped %", "adv. %"], why)

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

    # Schedulers (--schedule), both modes.
    sched_rows = load("schedule")
    s_sched = summarize(sched_rows)
    if s_sched:
        write_csv(os.path.join(res, "schedule_summary.csv"), list(s_sched[0].keys()), s_sched)
    fill["schedule_table"] = schedule_rows(s_sched) if s_sched else "(not run)"
    fill["schedule_size"] = (f"{s_sched[0]['width']}x{s_sched[0]['height']}, "
                             f"{s_sched[0]['count']} spheres, occupancy {s_sched[0]['occ_target']} %"
                             if s_sched else "(not run)")
    fill["schedule_run"] = run_info_line(sched_rows)
    fill["checks"] = checks_line([objects, sizes, tiles, sched_rows] +
                                 [load(n) for n in ("big_objects", "big_size", "occ_sweep")])

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
        f"{info.get('jobs', '?')} jobs x {info.get('repeats', '?')} rounds per configuration, "
        f"load average at start "
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
