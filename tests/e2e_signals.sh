#!/usr/bin/env bash
# e2e_signals.sh — SIGINT and SIGTERM during a render (host/signals.c):
#   - serial: exit 130 (SIGINT) or 143 (SIGTERM), one line on stderr
#     saying so, no file in the output's folder (image, stats, temporary)
#     but the journal of the finished tiles (host/output/journal.h), which the
#     line then names with the way to resume (tests/e2e_resume.sh resumes);
#   - under mpirun (3 ranks): SIGTERM and SIGINT to mpirun (which forwards
#     SIGTERM to every rank): mpirun exits non-zero, no rank left running,
#     no file written but the journal (the master's line is printed, but mpirun may end
#     before it forwards it: counted, not required).
# The renders are long (a few seconds at least); the signal comes about a
# second after the start (serial), or once the progress bar shows that the
# master hands out tiles (mpirun), while the tiles are traced.
# Usage: tests/e2e_signals.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

mpi_sandbox
slow_scene "$T/slow.pov"
LONG=(--width 3000 --height 3000)

# nothing_written DIR: DIR holds only the captured stdout and stderr, and
# the journal (o.png.journal) if any tile was finished
nothing_written() { [ -z "$(ls -A "$1" | grep -v -e '^out$' -e '^err$' -e '^o\.png\.journal$')" ]; }
# journal_named DIR: no journal, or the line names it and --resume
journal_named() { [ ! -e "$1/o.png.journal" ] || grep -q "o.png.journal: the same command with --resume" "$1/err"; }

# stopped NAME EXPECTED_STATUS SIGNAL_WORD
stopped() {
    local d=$T/$1 rc=$2 want=$3 word=$4
    if [ "$rc" = "$want" ] && [ "$(wc -l <"$d/err")" = 1 ] &&
        grep -q "csgtrace: .*($word): the render stopped" "$d/err" && nothing_written "$d" &&
        journal_named "$d"; then
        ok "$1: exit $rc, one line, nothing written but the journal it names"
    else
        ko "$1: exit $rc (wanted $want), stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"
    fi
}

for sig in INT TERM; do
    want=$([ $sig = INT ] && echo 130 || echo 143)
    d=$T/serial-$sig
    mkdir -p "$d"
    "$BIN" render "$T/slow.pov" "${LONG[@]}" --mode serial -o "$d/o.png" --stats "$d/o.json" \
        >"$d/out" 2>"$d/err" &
    pid=$!
    sleep 1
    kill -$sig $pid
    wait $pid
    stopped serial-$sig $? $want SIG$sig
done

for sig in TERM INT; do
    d=$T/mpi-$sig
    mkdir -p "$d"
    timeout -s KILL 120 mpirun --bind-to none --oversubscribe -np 3 "$BIN" render "$T/slow.pov" \
        "${LONG[@]}" --mode homo -o "$d/o.png" --stats "$d/o.json" --progress \
        >"$d/out" 2>"$d/err" &
    pid=$!
    # the progress bar shows once tiles come back: the master is rendering
    for _ in $(seq 600); do [ -s "$d/err" ] && break; sleep 0.1; done
    kill -$sig $pid
    wait $pid
    rc=$?
    sleep 1
    left=$(pgrep -f "render $T/slow.pov" | wc -l)
    # the master's line goes through mpirun's output forwarding, which
    # mpirun, ending at once, may drop: reported, not required
    said=$(grep -c 'the render stopped' "$d/err")
    if [ "$rc" != 0 ] && [ "$left" = 0 ] && nothing_written "$d"; then
        ok "mpirun SIG$sig: exit $rc, no rank left, nothing written but the journal (the master's line shown: $said)"
    else
        ko "mpirun SIG$sig: exit $rc, $left ranks left, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"
    fi
done

e2e_finish
