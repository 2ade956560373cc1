#!/usr/bin/env bash
# e2e_progress.sh — a worker's large answer reaches the master while the
# worker computes its next item (comm/mpi_link.h: link_progress; the tile
# runner calls it between bands, workers/tile.h).  Under Open MPI's shared
# memory without single-copy support (--mca btl_vader_single_copy_mechanism
# none: containers, some VMs; the network transports' rendezvous behave
# alike), a message over the eager limit (4 KB) moves on only when its
# sender calls MPI:
#   - the mechanism (tests/progress_probe.c: a 256 KB send, then 600 ms of
#     computing): with link_progress every millisecond the master has it
#     long before the computing ends; without, only after it (which shows
#     that the probe measures what it claims);
#   - the tile runner calls the hook between bands (tests/test_tile_run.c
#     checks the pixels are the same), so a render with tile 64 and 8-bit
#     answers of 12 KB, and one with --batch 8, give the serial image.
# Usage: tests/e2e_progress.sh
set -u
source "$(dirname "$0")/lib_e2e.sh"
mpi_sandbox
PROBE=build/tests/progress_probe
MPI=(timeout -s KILL 60 mpirun --oversubscribe --bind-to none --mca btl_vader_single_copy_mechanism none)

ms() { # ms MODE: the milliseconds the probe's master waited for the message
    "${MPI[@]}" -np 2 "$PROBE" "$1" 262144 600 2>/dev/null | sed -n 's/^received \([0-9.]*\) ms.*status 0)$/\1/p'
}
with=$(ms progress)
without=$(ms none)
python3 -c "import sys; sys.exit(0 if float('${with:-9999}') < 300 else 1)" &&
    ok "a large answer arrives while its sender computes and calls link_progress (${with} ms of 600)" ||
    ko "with link_progress: ${with:-no} ms (expected well under the 600 ms of computing)"
python3 -c "import sys; sys.exit(0 if float('${without:-0}') >= 550 else 1)" &&
    ok "without link_progress it waits for the computing to end (${without} ms): the probe shows the mechanism" ||
    ko "without link_progress: ${without:-no} ms (expected after the 600 ms of computing)"

"$BIN" render scenes/showcase.pov -o "$T/ref.png" --width 192 --height 144 >/dev/null 2>&1 || ko "serial"
for opt in "--tile 64" "--batch 8 --tile 16"; do
    for mode in homo hetero; do
        "${MPI[@]}" -np 3 "$BIN" render scenes/showcase.pov -o "$T/x.png" --width 192 --height 144 \
            --mode $mode $opt >"$T/x.log" 2>&1 && cmp -s "$T/ref.png" "$T/x.png" &&
            ok "$mode $opt, no single-copy: the serial image" ||
            ko "$mode $opt, no single-copy: $(tail -c 300 "$T/x.log")"
    done
done
e2e_finish
