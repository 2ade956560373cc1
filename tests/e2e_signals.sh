#!/usr/bin/env bash
# e2e_signals.sh — signals during a render (host/signals.c):
#   - serial: exit 130 (SIGINT) or 143 (SIGTERM), one line on stderr
#     saying so, no file in the output's folder (image, stats, temporary)
#     but the journal of the finished tiles (host/output/journal.h), which the
#     line then names with the way to resume (tests/e2e_resume.sh resumes);
#     the same for SIGHUP, SIGUSR1 and SIGPIPE (exit 128 + the signal); a
#     SIGHUP ignored at the start (nohup) stays ignored; SIGKILL leaves no
#     temporary file (the image is unnamed until renamed into place);
#   - SIGTERM during a long EXR write (the image module's), SIGKILL 0.3 s
#     later as mpirun does: stopped at once, the temporary file removed;
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
# the journal (o.png.journal, o.exr.journal) if any tile was finished
nothing_written() { [ -z "$(ls -A "$1" | grep -v -e '^out$' -e '^err$' -e '^o\.\(png\|exr\)\.journal$')" ]; }
# journal_named DIR: no journal, or the line names it and --resume
journal_named() {
    local j
    for j in o.png.journal o.exr.journal; do
        [ ! -e "$1/$j" ] || grep -q "$j: the same command with --resume" "$1/err" || return 1
    done
}

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

# every other signal that would end the process stops it the same way (it
# once killed it, leaving the streamed image's temporary file); exit 128 +
# the signal
for sig in HUP USR1 PIPE; do
    d=$T/serial-$sig
    mkdir -p "$d"
    # (a signal ignored when the suite began, as under nohup, stays ignored
    # in every child of the shell: its default action given back)
    env --default-signal="$sig" "$BIN" render "$T/slow.pov" --width 1400 --height 1400 -o "$d/o.png" --stats "$d/o.json" \
        >"$d/out" 2>"$d/err" &
    pid=$!
    sleep 0.5
    kill -$sig $pid
    wait $pid
    stopped serial-$sig $? $((128 + $(kill -l $sig))) SIG$sig
done

# SIGKILL (mpirun's, a second after its SIGTERM, to a rank that has not
# ended): no handler runs, and still no image and no temporary file is
# left, where the folder's file system has unnamed files (O_TMPFILE): the
# image has no name until it is renamed into place (file_temp in
# host/output/file_atomic.h); only the journal and the lock's file stay
# (host/output/claim.h: the next render takes it over)
d=$T/serial-KILL
mkdir -p "$d"
"$BIN" render "$T/slow.pov" "${LONG[@]}" --mode serial -o "$d/o.png" --stats "$d/o.json" \
    >"$d/out" 2>"$d/err" &
pid=$!
sleep 1
kill -KILL $pid
{ wait $pid; } 2>/dev/null # (the shell's "Killed")
rc=$?
left=$(ls -A "$d" | grep -v -e '^out$' -e '^err$' -e '^o\.png\.journal$' -e '^o\.png\.lock$')
if ! python3 -c 'import os, sys; os.close(os.open(sys.argv[1], os.O_TMPFILE | os.O_WRONLY))' "$d" \
    2>/dev/null; then
    echo "skip - SIGKILL: this file system has no unnamed files (O_TMPFILE): the named one stays"
elif [ $rc = 137 ] && [ -z "$left" ] && [ -e "$d/o.png.journal" ]; then
    ok "SIGKILL: nothing left but the journal and the lock's file"
else
    ko "SIGKILL: exit $rc, left: $left"
fi

# ... unless it was ignored when the render began (nohup): it stays ignored
d=$T/nohup
mkdir -p "$d"
(
    trap '' HUP
    "$BIN" render "$T/slow.pov" --width 600 --height 600 -o "$d/o.png" >/dev/null 2>"$d/err" &
    pid=$!
    sleep 0.2
    kill -HUP $pid
    wait $pid
)
rc=$?
[ $rc = 0 ] && [ -s "$d/o.png" ] && ok "SIGHUP ignored at the start (nohup): the render goes on, exit 0" ||
    ko "SIGHUP ignored at the start: exit $rc, stderr: $(head -c 300 "$d/err")"

# a signal during a long write of the image module's (EXR): the render stops
# at once, its temporary file removed (it once waited for the write to end,
# and mpirun's SIGKILL a moment after its SIGTERM left the hidden file)
d=$T/exr
mkdir -p "$d"
printf 'camera { location <0, 0, -4> look_at 0 }\nbackground { color rgb <0.2, 0.3, 0.4> }\n' >"$T/empty.pov"
"$BIN" render "$T/empty.pov" --width 4000 --height 4000 -o "$d/o.exr" >"$d/out" 2>"$d/err" &
pid=$!
for _ in $(seq 600); do ls "$d"/.o.exr.*.exr >/dev/null 2>&1 && break; sleep 0.02; done
kill -TERM $pid
sleep 0.3
kill -KILL $pid 2>/dev/null # (as mpirun does to a rank that outlives its SIGTERM)
wait $pid
stopped exr $? 143 SIGTERM

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
    # (the lock's file too: on a loaded machine mpirun's SIGKILL, a
    # second after its SIGTERM, may come before rank 0's handler has run)
    rm -f "$d/o.png.lock"
    if [ "$rc" != 0 ] && [ "$left" = 0 ] && nothing_written "$d"; then
        ok "mpirun SIG$sig: exit $rc, no rank left, nothing written but the journal (the master's line shown: $said)"
    else
        ko "mpirun SIG$sig: exit $rc, $left ranks left, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"
    fi
done

e2e_finish
