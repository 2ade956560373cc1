#!/usr/bin/env python3
"""povray_samples.py — the report of bench/povray_samples.sh.

    povray_samples.py WORK OUT.md MIN_AGREEMENT WIDTH HEIGHT

WORK holds one folder a scene (001, 002, ...) with the files the script
left there: `scene` (its path), `failed` (check or render: csgtrace stopped;
absent when it rendered), `check.err` and `render.log` (csgtrace's
message), `full_failed` (POV-Ray gave no image, or the comparison failed),
`compare.log` and `compare_flat.log` (tests/compare_images.py's lines for
the full and the flat image).
Everything is read as data.  Writes OUT.md: the counts by status, the
unsupported constructs by the number of scenes that stop on them first (the
roadmap), the other errors, and one row a scene.
"""
import datetime
import os
import re
import subprocess
import sys

SAMPLES = "/usr/share/doc/povray/examples/"
NEEDS = re.compile(r"unsupported: '([^']*)' \(declared at [^)]*\) needs (.*?) \([^()]*:\d+:\d+\), which")
PLAIN = re.compile(r"unsupported: (.*?) is not in csgtrace's language")
AGREE = re.compile(r"agreement ([0-9.]+)%")


def read(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return ""


def error_line(text):
    """The error line of a message (csgtrace prints one; #debug text may precede it)."""
    lines = [l for l in text.splitlines() if ": error: " in l]
    return lines[-1] if lines else text.strip().splitlines()[-1] if text.strip() else ""


def reason(line):
    """The message without its position and its macro/include chain."""
    r = line.split(": error: ", 1)[-1]
    return re.sub(r" \(in (macro|').*\)$", "", r)


def agreement(path):
    m = AGREE.search(read(path))
    return float(m.group(1)) if m else None


def classify(folder, min_agreement):
    """(scene, status, construct, detail, full agreement, flat agreement)."""
    scene = read(os.path.join(folder, "scene"))
    failed = read(os.path.join(folder, "failed")).strip()
    if failed == "check":
        line = error_line(read(os.path.join(folder, "check.err")))
        m = NEEDS.search(line)
        if m:
            return scene, "unsupported", m.group(2), "via '%s'" % m.group(1), None, None
        m = PLAIN.search(line)
        if m:
            return scene, "unsupported", m.group(1), "", None, None
        return scene, "error", "", reason(line), None, None
    if failed == "render":
        line = error_line(read(os.path.join(folder, "render.log")))
        return scene, "error", "", "render: " + reason(line), None, None
    if failed:
        return scene, "error", "", "the %s step failed" % failed, None, None
    full = agreement(os.path.join(folder, "compare.log"))
    flat = agreement(os.path.join(folder, "compare_flat.log"))
    why = read(os.path.join(folder, "full_failed")).strip()
    if full is None:
        return scene, "no reference", "", "POV-Ray failed" if why == "povray" else why, None, flat
    status = "agrees" if full >= min_agreement else "differs"
    return scene, status, "", "", full, flat


def md(text):
    return text.replace("|", "\\|").replace("\n", " ")


def short(scene):
    return scene[len(SAMPLES):] if scene.startswith(SAMPLES) else scene


def commit():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
    except OSError:
        return "unknown"


def count_by(rows, key):
    counts = {}
    for r in rows:
        counts[key(r)] = counts.get(key(r), 0) + 1
    return sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))


STATUSES = ("agrees", "differs", "no reference", "unsupported", "error")


def write_report(rows, out, min_agreement, width, height):
    renders = [r for r in rows if r[1] in ("agrees", "differs", "no reference")]
    agree = sum(1 for r in rows if r[1] == "agrees")
    compared = sum(1 for r in rows if r[1] in ("agrees", "differs"))
    flat_ok = sum(1 for r in renders if r[5] is not None and r[5] >= min_agreement)
    lines = ["# POV-Ray 3.7's sample scenes in csgtrace", "",
             "Written by `bench/povray_samples.sh` (%s, commit %s): every scene of Debian's "
             "`povray-examples` checked with `csgtrace check` at %dx%d (clock 0, POV-Ray's "
             "include library); each one that parses is rendered as written by POV-Ray 3.7 "
             "and by csgtrace (PNG, no antialiasing, POV-Ray's default gamma handling) and the "
             "full images are compared pixel by pixel (every channel within 3/255); beside it "
             "the flat image (`csgtrace export --flat`: every surface shows its pigment; "
             "hit/miss alike, colours within 2.5/255, as `tests/crosscheck_povray.sh`)."
             % (datetime.date.today().isoformat(), commit(), width, height), "",
             "## Summary", "", "| status | scenes |", "| --- | ---: |",
             "| csgtrace renders the scene | %d |" % len(renders),
             "| ... its full image agrees with POV-Ray's on >= %g %% of the pixels | %d (%.1f %% of "
             "those compared) |" % (min_agreement, agree, 100.0 * agree / compared if compared else 0),
             "| ... agrees on fewer pixels | %d |" % sum(1 for r in rows if r[1] == "differs"),
             "| ... POV-Ray gave no image to compare | %d |"
             % sum(1 for r in rows if r[1] == "no reference"),
             "| ... its flat image agrees on >= %g %% of the pixels | %d |" % (min_agreement, flat_ok),
             "| stops on a construct csgtrace does not implement | %d |"
             % sum(1 for r in rows if r[1] == "unsupported"),
             "| stops on another error | %d |" % sum(1 for r in rows if r[1] == "error"),
             "| total | %d |" % len(rows), "",
             "Every scene that differs is explained one by one in "
             "[POVRAY_DIFFERENCES.md](POVRAY_DIFFERENCES.md): what was fixed, POV-Ray's own "
             "run-to-run randomness (area-light jitter, crand), the approximations."]
    lines += ["", "## What to support next", "",
              "The first unsupported construct each scene stops on (a declaration of an "
              "include file that uses one is named by that construct):", "",
              "| construct | scenes |", "| --- | ---: |"]
    for construct, n in count_by([r for r in rows if r[1] == "unsupported"], lambda r: r[2]):
        lines.append("| %s | %d |" % (md(construct), n))
    lines += ["", "## Other errors", "", "| error | scenes |", "| --- | ---: |"]
    for detail, n in count_by([r for r in rows if r[1] == "error"], lambda r: r[3]):
        lines.append("| %s | %d |" % (md(detail[:160]), n))
    lines += ["", "## Every scene", "",
              "| scene | status | first unsupported construct or error | full agreement % "
              "| flat agreement % |",
              "| --- | --- | --- | ---: | ---: |"]
    pct = lambda v: "%.2f" % v if v is not None else ""
    for scene, status, construct, detail, full, flat in sorted(rows, key=lambda r: r[0]):
        what = construct + (" (%s)" % detail if detail and construct else detail)
        lines.append("| %s | %s | %s | %s | %s |" % (md(short(scene)), status, md(what[:160]),
                                                    pct(full), pct(flat)))
    with open(out, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def main():
    if len(sys.argv) != 6:
        sys.exit("usage: povray_samples.py WORK OUT.md MIN_AGREEMENT WIDTH HEIGHT")
    work, out = sys.argv[1], sys.argv[2]
    min_agreement, width, height = float(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
    folders = sorted(os.path.join(work, d) for d in os.listdir(work)
                     if os.path.isdir(os.path.join(work, d)))
    rows = [classify(f, min_agreement) for f in folders]
    write_report(rows, out, min_agreement, width, height)
    counts = {s: sum(1 for r in rows if r[1] == s) for s in STATUSES}
    print("%s: %d scenes: %d render (%d agree, %d differ, %d without a reference), "
          "%d unsupported, %d errors"
          % (out, len(rows), counts["agrees"] + counts["differs"] + counts["no reference"],
             counts["agrees"], counts["differs"], counts["no reference"], counts["unsupported"],
             counts["error"]))


if __name__ == "__main__":
    main()
