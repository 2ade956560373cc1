#!/usr/bin/env python3
"""spd_report.py — the bookkeeping of bench/spd.sh (data in, data out; it
never runs anything).

  spd_report.py row JSON SCENE RENDERER RUN     a csgtrace --stats file as a CSV row
  spd_report.py tachyon LOG SCENE RUN            Tachyon's timings as a CSV row
  spd_report.py povray LOG SCENE RUN             POV-Ray's timings as a CSV row
  spd_report.py report RAW.csv IDENTICAL.txt OUT.md

CSV columns: scene, renderer, run, frame_s, trace_s, rays (empty: unknown),
cl_open (csgtrace hetero: when its OpenCL device opened; empty otherwise),
culled (csgtrace: tiles_culled), own_s (csgtrace: guess_cpu_s + cull_s, the
work hetero does that homo does not while its device stays closed) and
tiles_s (csgtrace: the workers' seconds on tiles, summed); the last three
are empty for the other renderers and in rows written before them.
The report takes the median of the runs of each scene and renderer and
writes one table: frame times, csgtrace's rays, and the ratios the SPD
issue asks for (Tachyon / csgtrace homo on Tachyon's view; POV-Ray trace /
csgtrace trace; hetero / homo, with --pass auto and always), then hetero
against homo round by round (each round's two runs side by side: their
ratio's median, its 95 % confidence interval and the verdict it allows,
its range, and hetero's own work), then the per-pixel cost
of the tetra series, then bench/SPD-notes.md (the reading of the numbers,
written by hand) when it exists.
"""
import csv
import json
import math
import os
import re
import statistics
import sys


def row(path, scene, renderer, run):
    with open(path) as f:
        j = json.load(f)
    trace = j["primary_s"] + j["secondary_s"]
    rays = j["rays"]["total"] if "total" in j["rays"] else sum(j["rays"].values())
    own = j.get("guess_cpu_s", 0) + j.get("cull_s", 0)
    tiles = sum(w["busy_s"] for w in j.get("workers", []))
    print(f"{scene},{renderer},{run},{j['wall_s']:.6f},{trace:.6f},{rays},{j.get('cl_open', '')},"
          f"{j.get('tiles_culled', 0)},{own:.6f},{tiles:.6f}")


# How each renderer's log states its times: the trace, then the rest of
# the frame; a time is "LABEL: 1.23 seconds" (Tachyon) or
# "LABEL: 0 hours ... (1.23 seconds)" (POV-Ray).
LOGS = {
    "tachyon": (r"{}:\s*([0-9.]+) seconds", "Ray Tracing Time",
                ["Scene Parsing Time", "Preprocessing Time", "Image I/O Time"]),
    "povray": (r"{}:.*?\(([0-9.]+) seconds\)", "Trace Time", ["Parse Time", "Bounding Time"]),
}


def timings(renderer, path, scene, run):
    pattern, trace_label, others = LOGS[renderer]
    with open(path, errors="replace") as f:
        text = f.read()

    def seconds(label):
        m = re.search(pattern.format(label), text)
        return float(m.group(1)) if m else 0.0

    trace = seconds(trace_label)
    frame = trace + sum(seconds(label) for label in others)
    m = re.search(r"Rays:\s*([0-9]+)", text) if renderer == "povray" else None
    print(f"{scene},{renderer},{run},{frame:.6f},{trace:.6f},{m.group(1) if m else ''},,,,")


RENDERERS = ["serial", "homo", "hetero", "hetero-always", "homo-tview", "tachyon", "povray"]


def read_runs(raw):
    runs = {}
    with open(raw) as f:
        for r in csv.DictReader(f):
            key = (r["scene"], r["renderer"])
            runs.setdefault(key, []).append(r)
    return runs


def medians(runs):
    out = {}
    for key, rs in runs.items():
        out[key] = {
            "frame": statistics.median(float(r["frame_s"]) for r in rs),
            "trace": statistics.median(float(r["trace_s"]) for r in rs),
            "rays": statistics.median(int(r["rays"]) for r in rs) if rs[0]["rays"] else None,
            "runs": len(rs),
            # (None: rows written before spd.sh recorded cl_open)
            "opened": None if rs[0].get("cl_open") is None else
            sum(r["cl_open"] in ("start", "work") for r in rs),  # (not "failed")
        }
    return out


def fmt(v):
    return "—" if v is None else f"{v:.3f}"


def ratio(a, b):
    return "—" if not a or not b else f"{a / b:.2f}"


def optional(rs, column):
    """The median of a column written only by newer rows (None: absent)."""
    values = [float(r[column]) for r in rs if r.get(column) not in (None, "")]
    return statistics.median(values) if values else None


def paired(runs, scene, a, b):
    """a / b of the frame, round by round (the runs of one round ran side
    by side): the sorted ratios."""
    frames = {key: {r["run"]: float(r["frame_s"]) for r in runs.get((scene, key), [])}
              for key in (a, b)}
    return sorted(frames[a][k] / frames[b][k] for k in frames[a] if frames[b].get(k))


def median_interval(values, confidence=0.95):
    """The distribution-free confidence interval of the median of `values`
    (sorted): its k-th smallest and k-th largest, k the largest rank with
    P(Binomial(n, 1/2) < k) <= (1 - confidence) / 2.  None when n is too
    small for any k (n < 6 at 95 %)."""
    n = len(values)
    tail, k = (1 - confidence) / 2, 0
    below = 0.0  # P(Binomial(n, 1/2) < k + 1)
    while k < n // 2:
        below += math.comb(n, k) / 2 ** n
        if below > tail:
            break
        k += 1
    return None if k == 0 else (values[k - 1], values[n - k])


def verdict(interval):
    """hetero / homo's interval against 1: `slower` or `faster` when all of
    it lies on one side, `tie` when it holds 1 (the rounds cannot tell)."""
    if interval is None:
        return "—"
    lo, hi = interval
    return "slower" if lo > 1 else "faster" if hi < 1 else "tie"


def hetero_lines(runs, m, scenes, full):
    """Hetero (--pass auto) against homo, round by round: every round, the
    `full` ones and those of spd.sh --pairs."""
    pairs = max(v["runs"] for (_, renderer), v in m.items() if renderer == "homo")
    lines = [
        "",
        "Hetero (`--pass auto`) against homo, round by round.",
    ] + ([f"Of {pairs} rounds: the table's {full} and {pairs - full} of homo and hetero alone"
          " (`spd.sh --pairs`)."] if pairs > full else []) + [
        "The two ran side by side",
        "in each round, in turn first: `per round` is the median of the rounds' hetero /",
        "homo frame ratios and their range; `95 % interval`: where that median lies",
        "with 95 % confidence (order statistics, no assumption on the noise), and",
        "`verdict` what it says: `slower` or `faster` when the whole interval lies on one",
        "side of 1, `tie` when it holds 1; `faster` the rounds hetero took less time in.",
        "With many scenes some verdicts at 95 % come by chance alone (one in 20 scenes",
        "where nothing differs, on average): `all scenes` is the verdict of the interval",
        "at 1 - 0.05 / scenes (Bonferroni), which holds with 95 % for all the scenes at",
        "once.",
        "`own work`: rank 0's guess of the frame's work and the master's cull checks",
        "(`guess_cpu_s` + `cull_s`), what hetero does that homo does not while its",
        "device stays closed, against the workers' seconds on tiles (medians).",
        "",
        "| scene | tiles culled | opened | hetero / homo | per round | 95 % interval | verdict | all scenes | faster | own work (ms) | own / tiles |",
        "|---|---:|---:|---:|---:|---:|---|---|---:|---:|---:|",
    ]
    for s in scenes:
        ratios = paired(runs, s, "hetero", "homo")
        if not ratios:
            continue
        hs = runs[(s, "hetero")]
        culled, own, tiles = (optional(hs, c) for c in ("culled", "own_s", "tiles_s"))
        g = m[(s, "hetero")]
        opened = "—" if g["opened"] is None else f"{g['opened']}/{g['runs']}"
        faster = sum(x < 1 for x in ratios)
        interval = median_interval(ratios)
        family = median_interval(ratios, 1 - 0.05 / len(scenes))
        lines.append(
            f"| {s} | {'—' if culled is None else f'{culled:.0f}'} | {opened} | "
            f"{ratio(g['frame'], m[(s, 'homo')]['frame'])} | "
            f"{statistics.median(ratios):.3f} [{ratios[0]:.2f}-{ratios[-1]:.2f}] | "
            f"{'—' if interval is None else f'{interval[0]:.3f}-{interval[1]:.3f}'} | "
            f"{verdict(interval)} | {verdict(family)} | {faster}/{len(ratios)} | {'—' if own is None else f'{own * 1e3:.2f}'} | "
            f"{'—' if not own or not tiles else f'{own / tiles * 100:.2f} %'} |")
    return lines


def full_rounds(runs):
    """The (scene, round) pairs in which every renderer ran: those of
    csgtrace serial, which spd.sh --pairs leaves out."""
    return {(r["scene"], r["run"]) for (_, renderer), rs in runs.items() if renderer == "serial"
            for r in rs}


def only_rounds(runs, keep):
    """The runs of the rounds in `keep` alone."""
    out = {}
    for key, rs in runs.items():
        kept = [r for r in rs if (r["scene"], r["run"]) in keep]
        if kept:
            out[key] = kept
    return out


def report(raw, identical, out_path):
    every_run = read_runs(raw)
    # (the table compares renderers: the rounds they all ran in; the
    # round-by-round hetero table takes the --pairs rounds too)
    runs = only_rounds(every_run, full_rounds(every_run))
    m = medians(runs)
    scenes = sorted({s for s, _ in m})
    same = {}
    with open(identical) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 2:
                same[parts[0]] = parts[1]
    rounds = max(v["runs"] for v in m.values())
    lines = [
        "# SPD benchmark: csgtrace, Tachyon and POV-Ray on Eric Haines' scenes",
        "",
        f"Written by `bench/spd.sh` (medians of {rounds} interleaved rounds, 512x512, this",
        "machine: 2 cores). Frame = parse + build + trace + write, in seconds; csgtrace",
        "homo/hetero run 1 master + 2 workers under mpirun (launch not counted).",
        "`tview`: csgtrace homo on the file with Tachyon's fixed 53.13 degree view (the",
        "same work as Tachyon, which ignores `angle`). POV-Ray renders `csgtrace export`.",
        "Ratios above 1 favour csgtrace. `hetero`: the default `--pass auto` (`opened`: in",
        "how many of its runs rank 0's guess opened the OpenCL device); `always`: hetero",
        "`--pass always`. `same`: serial, homo and both hetero images bit-identical.",
        "",
        "| scene | serial | homo | hetero | opened | always | homo tview | Tachyon | Tachyon / tview | POV trace | POV trace / homo trace | hetero / homo | always / homo | rays (M) | same |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for s in scenes:
        g = lambda r, k="frame": m.get((s, r), {}).get(k)
        rays = g("serial", "rays")
        opened = ("—" if g("hetero") is None or g("hetero", "opened") is None
                  else f"{g('hetero', 'opened')}/{g('hetero', 'runs')}")
        lines.append(
            f"| {s} | {fmt(g('serial'))} | {fmt(g('homo'))} | {fmt(g('hetero'))} | {opened} | "
            f"{fmt(g('hetero-always'))} | "
            f"{fmt(g('homo-tview'))} | {fmt(g('tachyon'))} | {ratio(g('tachyon'), g('homo-tview'))} | "
            f"{fmt(g('povray', 'trace'))} | {ratio(g('povray', 'trace'), g('homo', 'trace'))} | "
            f"{ratio(g('hetero'), g('homo'))} | {ratio(g('hetero-always'), g('homo'))} | "
            f"{'—' if rays is None else f'{rays / 1e6:.2f}'} | {same.get(s, '?')} |")
    lines += hetero_lines(every_run, medians(every_run), scenes, rounds)
    tetra = [s for s in scenes if s.startswith("tetra")]
    if tetra:
        lines += ["", "Tetra series, csgtrace serial trace time per pixel (us):", ""]
        for s in tetra:
            t = m.get((s, "serial"), {}).get("trace")
            lines.append(f"- {s}: {fmt(None if t is None else t / (512 * 512) * 1e6)}")
    lines += ["", "![contact sheet: csgtrace, Tachyon, POV-Ray per scene](spd/sheet.png)", ""]
    notes = os.path.join(os.path.dirname(out_path), "SPD-notes.md")
    if os.path.exists(notes):  # the reading of the numbers, kept by hand
        with open(notes) as f:
            lines += ["", f.read()]
    with open(out_path, "w") as f:
        f.write("\n".join(lines))


def main(argv):
    if len(argv) >= 6 and argv[1] == "row":
        row(argv[2], argv[3], argv[4], argv[5])
    elif len(argv) >= 5 and argv[1] in ("tachyon", "povray"):
        timings(argv[1], argv[2], argv[3], argv[4])
    elif len(argv) >= 5 and argv[1] == "report":
        report(argv[2], argv[3], argv[4])
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
