#!/usr/bin/env bash
# e2e_resume.sh — the journal and --resume (host/output/journal.h):
#   - serial: SIGINT once tiles are finished leaves only OUT.journal; the
#     same command with --resume finishes it, the image equal pixel for
#     pixel to an uninterrupted render, the journal removed, the stats
#     counting tiles_resumed and tiles_rendered;
#   - mpirun (3 ranks): kill -9 of mpirun half-way; the orphaned master
#     stops by itself (no rank left); --resume in hetero mode (a homo
#     journal: every mode gives the same pixels) gives the identical image
#     and resumes at least every tile the progress bar had counted (no
#     finished tile is lost, only those in flight);
#   - the same to PNG (the workers send the 8-bit file's bytes and the
#     journal keeps their stand-ins, comm/pixels.h): the resumed PNG is
#     byte-identical to an uninterrupted one; that journal renamed for an
#     EXR output is refused (exit 2: the pixel format differs);
#   - under a file-size limit (ulimit -f) the journal's writes fail with
#     one warning naming the limit, the image's with an error naming it
#     (exit 1), a render and its --resume alike; no SIGXFSZ;
#   - a journal of another render (another --depth) is refused, exit 2,
#     naming what differs, and left as it was; a file that is not a journal
#     likewise; a damaged record is skipped, its tile rendered again, the
#     valid records after it kept (the image still identical); a link at
#     the journal's name is never followed; --resume without a journal
#     renders it all;
#     two renders of one output at once: the second is refused, also while
#     the first still reads its scene (the output's lock, OUT.lock, comes
#     before any file); --stats naming the journal is refused.
# Every render of a pair runs with another MALLOC_PERTURB_: a byte of the
# flattened scene left uninitialised would change its hash (the journal's
# header) and fail the resume.
# Usage: tests/e2e_resume.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

mpi_sandbox
slow_scene "$T/slow.pov"
SIZE=(--width 1400 --height 1400) # (seconds: the first record waits JOURNAL_AFTER_S)
MPI=(timeout -s KILL 120 mpirun --bind-to none --oversubscribe -np 3)

MALLOC_PERTURB_=85 "$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$T/full.exr" >/dev/null 2>&1 ||
    ko "the uninterrupted render"
[ ! -e "$T/full.exr.journal" ] && ok "a finished render leaves no journal" ||
    ko "a finished render left its journal"

# records FILE: the tile records in a journal (its size past the header)
records() { python3 - "$1" <<'EOF'
import sys
data = open(sys.argv[1], 'rb').read()
end = data.find(b'\n.\n')
print(0 if end < 0 else len(data) - end - 3)
EOF
}

# wait_records JOURNAL: until it holds at least one tile (at most 60 s)
wait_records() {
    for _ in $(seq 600); do
        [ -f "$1" ] && [ "$(records "$1")" -gt 0 ] && return 0
        sleep 0.1
    done
    return 1
}

# alive PATTERN: processes (not zombies) whose command line matches
alive() {
    local n=0
    for p in $(pgrep -f "$1"); do
        [ "$(ps -o stat= -p "$p" 2>/dev/null | cut -c1)" = Z ] || n=$((n + 1))
    done
    echo $n
}

# ---- serial: SIGINT, then --resume ------------------------------------------
d=$T/serial
mkdir -p "$d"
MALLOC_PERTURB_=170 "$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" >"$d/out" 2>"$d/err" &
pid=$!
wait_records "$d/o.exr.journal"
kill -INT $pid
wait $pid
rc=$?
left=$(ls -A "$d" | grep -v -e '^out$' -e '^err$' | tr '\n' ' ')
if [ $rc = 130 ] && [ "$left" = "o.exr.journal " ] &&
    grep -q "tiles are kept in $d/o.exr.journal: the same command with --resume" "$d/err"; then
    ok "SIGINT: exit 130, only the journal left, the line says how to resume"
else
    ko "SIGINT: exit $rc, left: $left, stderr: $(head -c 300 "$d/err")"
fi
MALLOC_PERTURB_=85 "$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" --resume \
    --stats "$d/s.json" >"$d/out" 2>"$d/err2"
rc=$?
if [ $rc = 0 ] && same "$T/full.exr" "$d/o.exr" && [ ! -e "$d/o.exr.journal" ] &&
    json "$d/s.json" "j['tiles_resumed'] > 0 and j['tiles_rendered'] > 0 and
        j['tiles_resumed'] + j['tiles_rendered'] + j['tiles_degenerate'] == j['tiles_total']"; then
    ok "--resume: the identical image, the journal gone, $(python3 -c "import json; j=json.load(open('$d/s.json')); print(j['tiles_resumed'], 'tiles resumed,', j['tiles_rendered'], 'rendered')")"
else
    ko "--resume: exit $rc, stderr: $(head -c 300 "$d/err2")"
fi

# ---- mpirun: kill -9 of mpirun, then --resume in hetero mode -------------------
d=$T/mpi
mkdir -p "$d"
BIG=(--width 2000 --height 2000) # (long enough to be killed half-way on 2 cores, after
                                  # the first record: JOURNAL_AFTER_S)
MALLOC_PERTURB_=85 "${MPI[@]}" "$BIN" render "$T/slow.pov" "${BIG[@]}" --mode homo \
    -o "$d/full.exr" >/dev/null 2>&1 || ko "the uninterrupted render under mpirun"
MALLOC_PERTURB_=170 "${MPI[@]}" "$BIN" render "$T/slow.pov" "${BIG[@]}" --mode homo -o "$d/o.exr" --progress \
    >"$d/out" 2>"$d/err" &
pid=$!
wait_records "$d/o.exr.journal"
kill -9 "$(pgrep -P $pid -x mpirun)" # (mpirun itself: $pid is its `timeout`)
wait $pid 2>/dev/null
shown=$(tr '\r' '\n' <"$d/err" | sed -n 's/.*\] \([0-9]*\)\/[0-9]* tiles.*/\1/p' | tail -1)
for _ in $(seq 50); do [ "$(alive "render $T/slow.pov")" = 0 ] && break; sleep 0.1; done
n=$(alive "render $T/slow.pov")
[ "$n" = 0 ] && ok "kill -9 mpirun: no rank left within 5 s" ||
    ko "kill -9 mpirun: $n ranks still running after 5 s"
"${MPI[@]}" "$BIN" render "$T/slow.pov" "${BIG[@]}" --mode hetero -o "$d/o.exr" --resume \
    --stats "$d/s.json" >"$d/out" 2>"$d/err2"
rc=$?
if [ $rc = 0 ] && same "$d/full.exr" "$d/o.exr" && [ ! -e "$d/o.exr.journal" ] &&
    json "$d/s.json" "j['tiles_resumed'] >= ${shown:-1} and
        j['tiles_resumed'] + j['tiles_rendered'] + j['tiles_degenerate'] == j['tiles_total']"; then
    ok "kill -9 mpirun, --resume (hetero): the identical image; resumed $(python3 -c "import json; print(json.load(open('$d/s.json'))['tiles_resumed'])") tiles >= the ${shown:-?} the bar had shown"
else
    ko "kill -9 mpirun, --resume: exit $rc (bar showed ${shown:-?}), stderr: $(head -c 300 "$d/err2")"
fi

# ---- mpirun to PNG: 8-bit results in the journal -----------------------------------
d=$T/png
mkdir -p "$d"
"${MPI[@]}" "$BIN" render "$T/slow.pov" "${BIG[@]}" --mode homo -o "$d/full.png" >/dev/null 2>&1 ||
    ko "the uninterrupted render to PNG under mpirun"
MALLOC_PERTURB_=170 "${MPI[@]}" "$BIN" render "$T/slow.pov" "${BIG[@]}" --mode homo -o "$d/o.png" \
    >"$d/out" 2>"$d/err" &
pid=$!
wait_records "$d/o.png.journal"
kill -9 "$(pgrep -P $pid -x mpirun)"
wait $pid 2>/dev/null
for _ in $(seq 50); do [ "$(alive "render $T/slow.pov")" = 0 ] && break; sleep 0.1; done
cp "$d/o.png.journal" "$d/o.exr.journal"
"$BIN" render "$T/slow.pov" "${BIG[@]}" -o "$d/o.exr" --resume >/dev/null 2>"$d/err-exr"
rc=$?
[ $rc = 2 ] && grep -q "the pixel format of the output (8-bit or float file) differs (the journal's pixels: 'rgb8', this render's: 'float')" "$d/err-exr" &&
    cmp -s "$d/o.png.journal" "$d/o.exr.journal" && [ ! -e "$d/o.exr" ] &&
    ok "an 8-bit journal resumed to EXR: exit 2, says the pixel format differs, kept" ||
    ko "an 8-bit journal resumed to EXR: exit $rc, stderr: $(head -c 300 "$d/err-exr")"
"${MPI[@]}" "$BIN" render "$T/slow.pov" "${BIG[@]}" --mode hetero -o "$d/o.png" --resume \
    --stats "$d/s.json" >"$d/out" 2>"$d/err2"
rc=$?
if [ $rc = 0 ] && cmp -s "$d/full.png" "$d/o.png" && [ ! -e "$d/o.png.journal" ] &&
    json "$d/s.json" "j['tiles_resumed'] > 0 and j['result_pixels'] == 'rgb8'"; then
    ok "kill -9 mpirun to PNG, --resume (hetero): the PNG byte-identical to an uninterrupted one"
else
    ko "kill -9 mpirun to PNG, --resume: exit $rc, stderr: $(head -c 300 "$d/err2")"
fi

# ---- a file-size limit (ulimit -f) --------------------------------------------------
# It once killed the render with SIGXFSZ (exit 153, no word) as the journal
# met it, and --resume the same way: now the journal's write fails with one
# warning naming the limit, the render goes on, and the image that cannot be
# written is an error naming it (exit 1), no file left but the journal.
d=$T/fsize
mkdir -p "$d"
limited() { bash -c 'ulimit -f 64 && exec "$@"' _ "$BIN" render "$T/slow.pov" \
    --width 1000 --height 1000 -o "$d/o.png" "$@" >/dev/null 2>"$d/err"; }
for flag in "" --resume; do
    limited $flag
    rc=$?
    left=$(ls -A "$d" | grep -v -e '^err$' | tr '\n' ' ')
    if [ $rc = 1 ] && [ "$(grep -c 'warning: cannot write the journal .*File too large: the file-size limit (ulimit -f) is 65536 bytes' "$d/err")" = 1 ] &&
        grep -q "error: cannot write $d/o.png: File too large: the file-size limit (ulimit -f) is 65536 bytes" "$d/err" &&
        [ "$left" = "o.png.journal " ]; then
        ok "ulimit -f 64 ${flag:-(a fresh render)}: exit 1, the journal's warning and the image's error name the limit, only the journal left"
    else
        ko "ulimit -f 64 ${flag:-(a fresh render)}: exit $rc, left: $left, stderr: $(head -c 400 "$d/err")"
    fi
done
"$BIN" render "$T/slow.pov" --width 1000 --height 1000 -o "$d/o.png" --resume \
    --stats "$d/s.json" >/dev/null 2>"$d/err"
rc=$?
[ $rc = 0 ] && json "$d/s.json" "j['tiles_resumed'] > 0" && [ ! -e "$d/o.png.journal" ] &&
    ok "... then --resume without the limit: exit 0, from the journal's tiles" ||
    ko "--resume after the limit: exit $rc, stderr: $(head -c 300 "$d/err")"
rm -f "$d"/*
bash -c 'ulimit -f 64 && exec "$@"' _ "$BIN" render "$T/slow.pov" --width 48 --height 48 \
    --tile 1 -o "$d/small.png" --tile-log "$d/log.jsonl" >/dev/null 2>"$d/err"
rc=$?
[ $rc = 1 ] && grep -q "error: cannot write $d/log.jsonl: File too large: the file-size limit (ulimit -f) is 65536 bytes" "$d/err" &&
    [ -z "$(ls -A "$d" | grep -v -e '^err$' -e '^small.png.journal$')" ] &&
    ok "a tile log over the file-size limit: exit 1, said with the limit, no image, log or temporary file left" ||
    ko "a tile log over the file-size limit: exit $rc, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"
rm -f "$d"/*
bash -c 'ulimit -f 1 && exec "$@"' _ "$BIN" render "$T/slow.pov" --width 64 --height 64 \
    -o "$d/small.exr" >/dev/null 2>"$d/err"
rc=$?
[ $rc = 1 ] && grep -q "^csgtrace: error: $d/small.exr: .*(the file met the file-size limit (ulimit -f) of 1024 bytes)$" "$d/err" &&
    [ -z "$(ls -A "$d" | grep -v -e '^err$')" ] &&
    ok "an EXR over the file-size limit (the image module): exit 1, said with the limit, no file left" ||
    ko "an EXR over the file-size limit: exit $rc, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"

# ---- journals that do not fit ----------------------------------------------------
# an interrupted render to resume from, again (serial, SIGTERM)
interrupted() {
    rm -f "$1" "$1.journal"
    "$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$1" >/dev/null 2>&1 &
    local p=$!
    wait_records "$1.journal"
    kill -TERM $p
    wait $p
}
d=$T/bad
mkdir -p "$d"
interrupted "$d/o.exr"
cp "$d/o.exr.journal" "$d/copy"
"$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" --resume --depth 3 >/dev/null 2>"$d/err"
rc=$?
if [ $rc = 2 ] && grep -q "written for another render: the trace depth differs" "$d/err" &&
    cmp -s "$d/copy" "$d/o.exr.journal" && [ ! -e "$d/o.exr" ]; then
    ok "another --depth: exit 2, says the depth differs, the journal kept as it was"
else
    ko "another --depth: exit $rc, stderr: $(head -c 300 "$d/err")"
fi

# damaged records, the first and one half-way: each is skipped (its tile
# rendered again), every valid record after it kept (a damaged record once
# ended the journal: every tile after it was rendered again); the image is
# still exact
whole=$(python3 - "$d/o.exr.journal" <<'EOF'
import struct, sys
p = sys.argv[1]
data = bytearray(open(p, 'rb').read())
end = data.find(b'\n.\n') + 3
size = 4 if b'\npixels float\n' in data[:end] else 1
at, whole = end, 0  # the whole records, before the damage
while at + 32 <= len(data):
    w, h = struct.unpack_from('<II', data, at + 16)
    at += 32 + w * h * 3 * size + 8
    whole += at <= len(data)
data[end + 40] ^= 0x40  # the first record's pixels
data[end + (len(data) - end) // 2] ^= 0x40
open(p, 'wb').write(data)
print(whole)
EOF
)
"$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" --resume --stats "$d/s.json" \
    >/dev/null 2>"$d/err"
rc=$?
if [ $rc = 0 ] && same "$T/full.exr" "$d/o.exr" && grep -q "not a whole, valid tile" "$d/err" &&
    json "$d/s.json" "j['tiles_resumed'] > 0"; then
    ok "a damaged record: said, the tiles from it rendered again, the image identical"
else
    ko "a damaged record: exit $rc, stderr: $(head -c 300 "$d/err")"
fi
json "$d/s.json" "j['tiles_resumed'] == $whole - 2" &&
    ok "two damaged records (the first, one half-way): the other $((whole - 2)) of $whole tiles resumed" ||
    ko "two damaged records: $(python3 -c "import json; print(json.load(open('$d/s.json'))['tiles_resumed'])" 2>&1) tiles resumed of $whole records"

echo "not a journal" >"$d/o.exr.journal"
"$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" --resume >/dev/null 2>"$d/err"
rc=$?
[ $rc = 2 ] && grep -q "is not a csgtrace journal" "$d/err" &&
    [ "$(cat "$d/o.exr.journal")" = "not a journal" ] &&
    ok "a file that is not a journal: exit 2, left as it was" ||
    ko "not a journal: exit $rc, stderr: $(head -c 300 "$d/err")"

echo "precious" >"$d/target"
rm -f "$d/o.exr.journal"
ln -s "$d/target" "$d/o.exr.journal"
for flag in --resume ""; do
    "$BIN" render "$T/slow.pov" --width 64 --height 64 -o "$d/o.exr" $flag >/dev/null 2>"$d/err"
    rc=$?
    [ $rc = 1 ] && [ "$(cat "$d/target")" = precious ] && [ -L "$d/o.exr.journal" ] &&
        ok "a link at the journal's name ${flag:-(no --resume)}: refused, its target untouched" ||
        ko "a link at the journal's name ${flag:-(no --resume)}: exit $rc, target: $(head -c 40 "$d/target")"
done
rm -f "$d/o.exr.journal"

"$BIN" render "$T/slow.pov" --width 64 --height 64 -o "$d/small.exr" --resume >/dev/null \
    2>"$d/err"
rc=$?
[ $rc = 0 ] && grep -q "no journal .* to resume from: the render starts from the beginning" \
    "$d/err" && [ -f "$d/small.exr" ] && [ ! -e "$d/small.exr.journal" ] &&
    ok "--resume without a journal: said, rendered in full" ||
    ko "--resume without a journal: exit $rc, stderr: $(head -c 300 "$d/err")"

"$BIN" render "$T/slow.pov" --width 64 --height 64 -o "$d/small.exr" \
    --stats "$d/small.exr.journal" >/dev/null 2>"$d/err"
rc=$?
[ $rc = 2 ] && grep -q "the output's journal" "$d/err" &&
    ok "--stats naming the output's journal: exit 2" ||
    ko "--stats naming the journal: exit $rc, stderr: $(head -c 300 "$d/err")"
"$BIN" render "$T/slow.pov" --width 64 --height 64 -o "$d/small.exr" \
    --tile-log "$d/small.exr.lock" >/dev/null 2>"$d/err"
rc=$?
[ $rc = 2 ] && grep -q "the output's lock" "$d/err" &&
    ok "--tile-log naming the output's lock: exit 2" ||
    ko "--tile-log naming the lock: exit $rc, stderr: $(head -c 300 "$d/err")"

# two renders of one output at once (the journal is locked from the start,
# before its first record)
rm -f "$d/o.exr" "$d/o.exr.journal"
"$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 600); do [ -f "$d/o.exr.journal" ] && break; sleep 0.05; done
"$BIN" render "$T/slow.pov" "${SIZE[@]}" -o "$d/o.exr" >/dev/null 2>"$d/err"
rc=$?
kill -TERM $pid
wait $pid
[ $rc = 1 ] && grep -q "is in use by another render" "$d/err" &&
    ok "a second render of the same output while the first runs: refused" ||
    ko "a second render of the same output: exit $rc, stderr: $(head -c 300 "$d/err")"

# ... and while the first still reads its scene (no journal yet): the lock
# (OUT.lock, never renamed) is taken before anything, so the second stops at
# once naming it; each once made a journal of its own and both ran
cat >"$d/parse.pov" <<'POV'
#declare I = 0;
#while (I < 1000000) #declare I = I + 1; #end
camera { location <0, 0, -4> look_at 0 }
light_source { <2, 4, -3> color rgb 1 }
sphere { 0, 1 pigment { color rgb 1 } }
POV
rm -f "$d/p.png" "$d/p.png.journal"
"$BIN" render "$d/parse.pov" --width 64 --height 64 -o "$d/p.png" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 100); do [ -e "$d/p.png.lock" ] && break; sleep 0.05; done
"$BIN" render "$T/slow.pov" --width 64 --height 64 -o "$d/p.png" >/dev/null 2>"$d/err"
rc=$?
wait $pid
rc_first=$?
[ $rc = 1 ] && [ $rc_first = 0 ] && [ "$(wc -l <"$d/err")" = 1 ] &&
    grep -q "p.png is in use by another render (process $pid holds its lock $d/p.png.lock)" "$d/err" &&
    [ ! -e "$d/p.png.lock" ] && [ ! -e "$d/p.png.journal" ] &&
    ok "a second render while the first reads its scene: refused at once, naming the lock; the lock gone after" ||
    ko "a second render while the first reads its scene: exit $rc (first: $rc_first), stderr: $(head -c 300 "$d/err")"

e2e_finish
