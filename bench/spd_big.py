#!/usr/bin/env python3
"""spd_big.py — millions of primitives: the SPD's tetra beyond the shipped
tetra8 (65 536 triangles), up to tetra11 (4 194 304), made by
bench/spd_subdivide.py, rendered at 512x512 by csgtrace serial, homo and
hetero (1 master + 2 workers under mpirun) and by Tachyon (2 threads), in
R interleaved rounds; bench/SPD-BIG.md gets the medians: the set-up (parse,
flatten, BVH: `setup_s`) a triangle, the trace, the frame, the blob a
triangle, the peak memory (the largest process: rank 0), Tachyon's parse
and preprocessing beside them, and whether the three modes' images are
the same bit for bit.

Usage: bench/spd_big.py [--runs R] [--sizes 9,10,11] [--nff DIR] [--out DIR]
                        [--report FILE.md] [--report-only]
  (DIR: --nff, else $SPD_NFF, else ../shared/nff beside the repository;
  the generated files, 23 MB to 450 MB, go to OUT/work, not into git)
Needs: build/csgtrace, mpirun, tachyon (make deps-bench), oiiotool's idiff.
"""
import argparse
import csv
import json
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "csgtrace")
MPI = ["mpirun", "-np", "3", "--bind-to", "none"]
FIELDS = ["scene", "triangles", "renderer", "run", "setup_s", "trace_s", "frame_s",
          "process_s", "blob_bytes", "maxrss_kb"]
RENDERERS = ["serial", "homo", "hetero", "tachyon"]


def run_measured(cmd, log, cwd=None):
    """Runs cmd (stdout and stderr to log); its seconds and the largest
    resident size of it or any process it waited for (wait4), in KiB."""
    with open(log, "w") as out:
        t0 = time.monotonic()
        p = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, cwd=cwd)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        seconds = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit("spd_big: %s failed (status %d), see %s" % (" ".join(cmd), p.returncode, log))
    return seconds, usage.ru_maxrss


def scene_files(nff, work, sizes):
    """tetra8 as shipped, then tetraN for each size, made once."""
    base = os.path.join(nff, "tetra8.nff")
    if not os.path.exists(base):
        sys.exit("spd_big: %s not found (--nff DIR)" % base)
    scenes = [("tetra8", base)]
    for n in sizes:
        path = os.path.join(work, "tetra%d.nff" % n)
        if not os.path.exists(path):
            print("making %s" % path, file=sys.stderr)
            subprocess.run([sys.executable, os.path.join(ROOT, "bench", "spd_subdivide.py"),
                            base, str(n - 8), path + ".part"], check=True, stdout=subprocess.DEVNULL)
            os.rename(path + ".part", path)
        scenes.append(("tetra%d" % n, path))
    return scenes


def run_csgtrace(name, path, mode, run, out):
    image = os.path.join(out, "img", "%s-%s.png" % (name, mode))
    stats = os.path.join(out, "work", "%s-%s.json" % (name, mode))
    cmd = [BIN, "render", path, "-o", image, "--mode", mode, "--stats", stats]
    seconds, rss = run_measured(cmd if mode == "serial" else MPI + cmd,
                                os.path.join(out, "work", "%s-%s.log" % (name, mode)))
    with open(stats) as f:
        j = json.load(f)
    return {"renderer": mode, "run": run, "setup_s": j["setup_s"],
            "trace_s": j["primary_s"] + j["secondary_s"], "frame_s": j["wall_s"],
            "process_s": seconds, "blob_bytes": j["blob_bytes"], "maxrss_kb": rss}


def tachyon_seconds(text, label):
    m = re.search(r"%s:\s*([0-9.]+) seconds" % label, text)
    return float(m.group(1)) if m else 0.0


def run_tachyon(name, path, run, out):
    log = os.path.join(out, "work", "%s-tachyon.log" % name)
    seconds, rss = run_measured(["tachyon", path, "-o", os.path.join(out, "img", name + "-tachyon.tga"),
                                 "-format", "TARGA", "-res", "512", "512", "-numthreads", "2"],
                                log, cwd=os.path.join(out, "work"))
    with open(log, errors="replace") as f:
        text = f.read()
    setup = tachyon_seconds(text, "Scene Parsing Time") + tachyon_seconds(text, "Preprocessing Time")
    trace = tachyon_seconds(text, "Ray Tracing Time")
    return {"renderer": "tachyon", "run": run, "setup_s": setup, "trace_s": trace,
            "frame_s": setup + trace + tachyon_seconds(text, "Image I/O Time"),
            "process_s": seconds, "blob_bytes": "", "maxrss_kb": rss}


def triangles_of(path):
    with open(path) as f:
        return sum(1 for line in f if line.startswith("p 3"))


def identical(out, name):
    a = os.path.join(out, "img", "%s-serial.png" % name)
    return all(subprocess.run(["idiff", "-fail", "0", "-warn", "0", a,
                               os.path.join(out, "img", "%s-%s.png" % (name, m))],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0
               for m in ("homo", "hetero"))


def measure(args):
    os.makedirs(os.path.join(args.out, "work"), exist_ok=True)
    os.makedirs(os.path.join(args.out, "img"), exist_ok=True)
    env = os.environ
    env.update({"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
                "OMPI_MCA_pml": "ob1", "OMPI_MCA_rmaps_base_oversubscribe": "1"})
    env.setdefault("POCL_CACHE_DIR", os.path.join(ROOT, "build", "pocl-cache"))
    scenes = scene_files(args.nff, os.path.join(args.out, "work"), args.sizes)
    counts = {name: triangles_of(path) for name, path in scenes}
    # warm-ups, not recorded: the file cache, and the OpenCL program's cache
    run_csgtrace(scenes[0][0], scenes[0][1], "serial", 0, args.out)
    subprocess.run([BIN, "render", scenes[0][1], "-o", os.path.join(args.out, "work", "warm.png"),
                    "--mode", "hetero", "--width", "16"], stdout=subprocess.DEVNULL, check=True)
    raw = os.path.join(args.out, "raw.csv")
    with open(raw, "w", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        w.writeheader()
        for run in range(1, args.runs + 1):
            for name, path in scenes:
                print("round %d/%d: %s" % (run, args.runs, name), file=sys.stderr)
                pair = ["homo", "hetero"] if run % 2 else ["hetero", "homo"]
                rows = [run_csgtrace(name, path, m, run, args.out) for m in ["serial"] + pair]
                rows.append(run_tachyon(name, path, run, args.out))
                for r in rows:
                    w.writerow(dict(r, scene=name, triangles=counts[name]))
                f.flush()
    with open(os.path.join(args.out, "identical.txt"), "w") as f:
        for name, _ in scenes:
            f.write("%s %s\n" % (name, "identical" if identical(args.out, name) else "DIFFERENT"))


def med(rows, key):
    values = [float(r[key]) for r in rows]
    return statistics.median(values), min(values), max(values)


def fmt(m, digits=3):
    return "%.*f (%.*f-%.*f)" % (digits, m[0], digits, m[1], digits, m[2])


def report(args):
    with open(os.path.join(args.out, "raw.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(args.out, "identical.txt")) as f:
        same = dict(line.split() for line in f if line.strip())
    scenes = sorted({r["scene"] for r in rows}, key=lambda s: int(s[5:]))
    by = {(s, m): [r for r in rows if r["scene"] == s and r["renderer"] == m]
          for s in scenes for m in RENDERERS}
    runs = max(int(r["run"]) for r in rows)
    out = ["# Millions of primitives: the SPD's tetra up to 4 194 304 triangles", "",
           "Written by `bench/spd_big.py` (medians of %d interleaved rounds, min-max in"
           " brackets, 512x512, this machine: 2 cores). tetra8 is the shipped file; the"
           " larger ones are made from it by `bench/spd_subdivide.py` (each"
           " tetrahedron into its four half-size corners, as Haines' generator does)."
           " `set-up`: csgtrace's `setup_s` (parse, flatten, BVH), Tachyon's parse +"
           " preprocessing; `frame`: csgtrace's `wall_s` (the launch not counted),"
           " Tachyon's four phases; `peak`: the largest resident size of the process"
           " tree (under mpirun: rank 0, which parses and flattens); `blob`: the"
           " flattened scene each worker receives. `same`: serial, homo and hetero"
           " images bit-identical." % runs, "",
           "| scene | triangles | set-up serial (s) | set-up a triangle (us) | trace serial (s)"
           " | frame serial | frame homo | frame hetero | blob a triangle (B) | peak serial (MB)"
           " | peak a triangle (B) | peak homo (MB) | Tachyon set-up (s) | Tachyon trace (s)"
           " | Tachyon frame | Tachyon peak (MB) | same |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for s in scenes:
        ser, homo, het, tach = (by[(s, m)] for m in RENDERERS)
        n = int(ser[0]["triangles"])
        setup = med(ser, "setup_s")
        peak = med(ser, "maxrss_kb")[0] * 1024
        out.append("| %s | %d | %s | %.2f | %.3f | %.3f | %.3f | %.3f | %.0f | %.0f | %.0f | %.0f"
                   " | %.3f | %.3f | %.3f | %.0f | %s |" % (
                       s, n, fmt(setup), setup[0] / n * 1e6, med(ser, "trace_s")[0],
                       med(ser, "frame_s")[0], med(homo, "frame_s")[0], med(het, "frame_s")[0],
                       float(ser[0]["blob_bytes"]) / n, peak / 2**20, peak / n,
                       med(homo, "maxrss_kb")[0] / 1024, med(tach, "setup_s")[0],
                       med(tach, "trace_s")[0], med(tach, "frame_s")[0],
                       med(tach, "maxrss_kb")[0] / 1024, same.get(s, "?")))
    notes = os.path.join(ROOT, "bench", "SPD-BIG-notes.md")
    if os.path.exists(notes):
        with open(notes) as f:
            out += ["", f.read().rstrip()]
    with open(args.report, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--sizes", default="9,10,11")
    p.add_argument("--nff", default=os.environ.get("SPD_NFF",
                                                   os.path.join(ROOT, "..", "shared", "nff")))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "spd-big"))
    p.add_argument("--report", default=os.path.join(ROOT, "bench", "SPD-BIG.md"))
    p.add_argument("--report-only", action="store_true")
    args = p.parse_args()
    args.sizes = [int(x) for x in args.sizes.split(",") if x]
    if not args.report_only:
        measure(args)
    report(args)


if __name__ == "__main__":
    main()
