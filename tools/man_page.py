#!/usr/bin/env python3
"""man_page.py — csgtrace.1 from `csgtrace --help`.

    tools/man_page.py BUILD/csgtrace > csgtrace.1

The option table (host/options.h) makes --help; this turns that text into a
manual page, so the two never disagree.
"""
import subprocess
import sys


def roff(text):
    return text.replace("\\", "\\\\").replace("-", "\\-")


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    help_text = subprocess.run([argv[1], "--help"], check=True, capture_output=True,
                               text=True).stdout
    version = subprocess.run([argv[1], "--version"], check=True, capture_output=True,
                             text=True).stdout.split()[1]
    lines = help_text.splitlines()
    out = [f'.TH CSGTRACE 1 "" "csgtrace {version}" "User Commands"',
           ".SH NAME",
           "csgtrace \\- a parallel CSG ray tracer: OpenCL primary pass, MPI workers",
           ".SH SYNOPSIS", ".nf"]
    section = "synopsis"
    for line in lines:
        if line == "usage:":
            continue
        if line.startswith("options"):
            out += [".fi", ".SH OPTIONS", roff(line)]
            section = "options"
            continue
        if line.startswith("environment:"):
            out += [".SH ENVIRONMENT"]
            section = "environment"
            continue
        if section == "synopsis":
            out.append(roff(line.strip()))
        elif section == "options":
            body = line.strip()
            if not body.startswith("-"):  # a long spelling's help, on its own line
                out.append(roff(body))
                continue
            # "SPELLING   help [commands]": the spelling ends at the first run of 2 spaces
            cut = body.find("  ")
            spell, rest = (body[:cut], body[cut:].strip()) if cut > 0 else (body, "")
            out += [".TP", "\\fB" + roff(spell) + "\\fR"] + ([roff(rest)] if rest else [])
        else:
            body = line.strip()
            cut = body.find(" ")
            out += [".TP", "\\fB" + roff(body[:cut]) + "\\fR", roff(body[cut:].strip())]
    out += [".SH EXIT STATUS",
            "0 success; 1 any other failure; 2 bad input (the scene or the arguments), with "
            "one line \\fIfile:line:col: error: ...\\fR on stderr.",
            ".SH SEE ALSO", "mpirun(1), povray(1)"]
    print("\n".join(out))


if __name__ == "__main__":
    main(sys.argv)
