#!/usr/bin/env python3
"""spd_report.py — the bookkeeping of bench/spd.sh (data in, data out; it
never runs anything).

  spd_report.py row JSON SCENE RENDERER RUN     a csgtrace --stats file as a CSV row
  spd_report.py tachyon LOG SCENE RUN            Tachyon's timings as a CSV row
  spd_report.py povray LOG SCENE RUN             POV-Ray's timings as a CSV row
  spd_report.py report RAW.csv IDENTICAL.txt OUT.md

CSV columns: scene, renderer, run, frame_s, trace_s, rays (empty: unknown),
cl_open (csgtrace hetero: when its OpenCL device opened; empty otherwise).
The report takes the median of the runs of each scene and renderer and
writes one table: frame times, csgtrace's rays, and the ratios the SPD
issue asks for (Tachyon / csgtrace homo on Tachyon's view; POV-Ray trace /
csgtrace trace; hetero / homo, with --pass auto and always), then the sums and the per-pixel cost of
the tetra series, then bench/SPD-notes.md (the reading of the numbers,
written by hand) when it exists.
"""
import csv
import json
import os
import re
import statistics
import sys


def row(path, scene, renderer, run):
    with open(path) as f:
        j = json.load(f)
    trace = j["primary_s"] + j["secondary_s"]
    rays = j["rays"]["total"] if "total" in j["rays"] else sum(j["rays"].values())
    print(f"{scene},{renderer},{run},{j['wall_s']:.6f},{trace:.6f},{rays},{j.get('cl_open', '')}")


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
    print(f"{scene},{renderer},{run},{frame:.6f},{trace:.6f},{m.group(1) if m else ''},")


RENDERERS = ["serial", "homo", "hetero", "hetero-always", "homo-tview", "tachyon", "povray"]


def medians(raw):
    runs = {}
    with open(raw) as f:
        for r in csv.DictReader(f):
            key = (r["scene"], r["renderer"])
            runs.setdefault(key, []).append(r)
    out = {}
    for key, rs in runs.items():
        out[key] = {
            "frame": statistics.median(float(r["frame_s"]) for r in rs),
            "trace": statistics.median(float(r["trace_s"]) for r in rs),
            "rays": statistics.median(int(r["rays"]) for r in rs) if rs[0]["rays"] else None,
            "runs": len(rs),
            # (None: rows written before spd.sh recorded cl_open)
            "opened": None if rs[0].get("cl_open") is None else
            sum(r["cl_open"] not in ("", "never", "none") for r in rs),
        }
    return out


def fmt(v):
    return "—" if v is None else f"{v:.3f}"


def ratio(a, b):
    return "—" if not a or not b else f"{a / b:.2f}"


def report(raw, identical, out_path):
    m = medians(raw)
    scenes = sorted({s for s, _ in m})
    same = {}
    with open(identical) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 2:
                same[parts[0]] = parts[1]
    runs = max(v["runs"] for v in m.values())
    lines = [
        "# SPD benchmark: csgtrace, Tachyon and POV-Ray on Eric Haines' scenes",
        "",
        f"Written by `bench/spd.sh` (medians of {runs} interleaved rounds, 512x512, this",
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
