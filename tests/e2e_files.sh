#!/usr/bin/env bash
# e2e_files.sh — a render's output files, checked before its first tile
# (host/output/claim.h: claim_check_output; host/output/journal.c):
#   - `-o ""` (or `--stats ""`) is a usage error, exit 2, one line;
#   - an extension whose OpenImageIO writer makes no file (x.null, x.term)
#     is refused, exit 1, no file (it wrote an empty file, exit 0);
#   - a FIFO named like the image, the stats, the tile log or the journal is
#     refused, exit 1, and stays a FIFO (a FIFO or device node was replaced
#     by a regular file); so is a symbolic link at the image's name, its
#     target not made;
#   - --resume through a hard link to the journal is refused, exit 1, the
#     other name's file untouched (it was appended to and cut); as root,
#     so is a journal of another user's;
#   - a read-only journal does not block a fresh render: it is replaced
#     (run as an unprivileged user when root: root may write it anyway);
#   - the files a scene writes (#fopen ... write|append, #write): `check`
#     writes none, a render writes them beside its output (an appended one
#     grows by one render's text each time); a scene that writes the
#     output's name is refused, exit 2; a symbolic link at a written file's
#     name is refused, exit 1, and kept; a name that leaves the folder is an
#     error at the name, exit 2.
# Usage: tests/e2e_files.sh   (CSGTRACE_BIN: the binary, default build/csgtrace)
set -u
source "$(dirname "$0")/lib_e2e.sh"

cat >"$T/good.pov" <<'POV'
camera { location <0, 0, -4> look_at 0 }
light_source { <2, 4, -3> color rgb 1 }
sphere { 0, 1 pigment { color rgb <1, 0.5, 0.2> } }
POV
SMALL=(--width 16 --height 12)
d=$T/out
mkdir -p "$d"

# only EXPECTED... are in $d (besides err)
only() {
    local want got
    want=$(printf '%s\n' "$@" err | sort | tr '\n' ' ')
    got=$(ls -A "$d" | sort | tr '\n' ' ')
    [ "$want" = "$got" ]
}

# ---- names ----------------------------------------------------------------------
for opt in -o --stats; do
    args=(-o "$d/x.png")
    [ "$opt" = -o ] && args=() || true
    "$BIN" render "$T/good.pov" "${SMALL[@]}" "${args[@]}" "$opt" "" >/dev/null 2>"$d/err"
    rc=$?
    [ $rc = 2 ] && [ "$(wc -l <"$d/err")" = 1 ] &&
        grep -qx "csgtrace: error: $opt needs a file name, got an empty one" "$d/err" && only &&
        ok "$opt \"\": exit 2, one line: needs a file name" ||
        ko "$opt \"\": exit $rc, stderr: $(head -c 300 "$d/err")"
done

for ext in null term; do
    "$BIN" render "$T/good.pov" "${SMALL[@]}" -o "$d/x.$ext" >"$d/out.txt" 2>"$d/err"
    rc=$?
    rm -f "$d/out.txt"
    [ $rc = 1 ] && grep -q "x.$ext: cannot write this image format ('$ext'): OpenImageIO's '$ext' writer makes no file" "$d/err" &&
        only && ok "-o x.$ext: exit 1, refused (a writer that makes no file), nothing written" ||
        ko "-o x.$ext: exit $rc, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"
done

# ---- what is at an output's name ----------------------------------------------------
for what in image stats tile-log journal; do
    rm -f "$d"/*
    case $what in
    image) fifo=o.png args=() word="the output (-o)" ;;
    stats) fifo=s.json args=(--stats "$d/s.json") word="the stats (--stats)" ;;
    tile-log) fifo=l.jsonl args=(--tile-log "$d/l.jsonl") word="the tile log (--tile-log)" ;;
    journal) fifo=o.png.journal args=() word="the output's journal" ;;
    esac
    mkfifo "$d/$fifo"
    timeout 20 "$BIN" render "$T/good.pov" "${SMALL[@]}" -o "$d/o.png" "${args[@]}" \
        >/dev/null 2>"$d/err"
    rc=$?
    [ $rc = 1 ] && grep -qF "csgtrace: error: $word '$d/$fifo' is a FIFO: refusing to replace it with a file" "$d/err" &&
        [ -p "$d/$fifo" ] && only "$fifo" &&
        ok "a FIFO named like the $what: exit 1, refused, still a FIFO, nothing written" ||
        ko "a FIFO named like the $what: exit $rc, stderr: $(head -c 300 "$d/err"), files: $(ls -lA "$d" | tr '\n' ' ')"
done
rm -f "$d"/*

ln -s "$d/target.png" "$d/o.png"
"$BIN" render "$T/good.pov" "${SMALL[@]}" -o "$d/o.png" >/dev/null 2>"$d/err"
rc=$?
[ $rc = 1 ] && grep -q "'$d/o.png' is a symbolic link: refusing to replace it" "$d/err" &&
    [ -L "$d/o.png" ] && only o.png &&
    ok "a symbolic link at the image's name: exit 1, refused, the link kept, its target not made" ||
    ko "a symbolic link at the image's name: exit $rc, stderr: $(head -c 300 "$d/err")"
rm -f "$d"/*

# ---- the journal ------------------------------------------------------------------
# journal: a render that fails as its tile log is written (over the
# file-size limit) keeps its finished tiles in o.png.journal
journal() {
    rm -f "$d"/*
    bash -c 'ulimit -f 4 && exec "$@"' _ "$BIN" render "$T/good.pov" --width 8 --height 6 \
        --tile 1 -o "$d/o.png" --tile-log "$d/l.jsonl" >/dev/null 2>&1
    [ -s "$d/o.png.journal" ] || ko "no journal to resume from"
}
journal
ln "$d/o.png.journal" "$d/other"
cp "$d/other" "$T/other.copy"
"$BIN" render "$T/good.pov" --width 8 --height 6 --tile 1 -o "$d/o.png" --resume \
    >/dev/null 2>"$d/err"
rc=$?
[ $rc = 1 ] && grep -q "the journal $d/o.png.journal has other names (hard links): refusing to resume from it" "$d/err" &&
    cmp -s "$d/other" "$T/other.copy" && only o.png.journal other &&
    ok "--resume through a hard link to the journal: exit 1, refused, the other file untouched" ||
    ko "--resume through a hard link: exit $rc, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"

if [ "$(id -u)" = 0 ]; then
    journal
    chown 65534 "$d/o.png.journal"
    "$BIN" render "$T/good.pov" --width 8 --height 6 --tile 1 -o "$d/o.png" --resume \
        >/dev/null 2>"$d/err"
    rc=$?
    [ $rc = 1 ] && grep -q "the journal $d/o.png.journal belongs to another user: refusing" "$d/err" &&
        ok "--resume from another user's journal: exit 1, refused" ||
        ko "--resume from another user's journal: exit $rc, stderr: $(head -c 300 "$d/err")"
fi

# a read-only journal (its user's, not root, who may write it anyway)
as_user() {
    if [ "$(id -u)" != 0 ]; then
        "$@"
    elif command -v setpriv >/dev/null; then
        setpriv --reuid=65534 --regid=65534 --clear-groups "$@"
    else
        return 77
    fi
}
rm -f "$d"/*
chmod 711 "$T"
chmod 777 "$d"
as_user sh -c 'echo "an earlier journal" >"$1" && chmod 444 "$1"' _ "$d/o.png.journal"
as_user "$BIN" render "$T/good.pov" "${SMALL[@]}" -o "$d/o.png" >/dev/null 2>"$d/err"
rc=$?
if [ $rc = 77 ]; then
    ok "a read-only journal, a fresh render: (skipped: root without setpriv)"
elif [ $rc = 0 ] && [ -s "$d/o.png" ] && only o.png; then
    ok "a read-only journal, a fresh render (no --resume): exit 0, replaced"
else
    ko "a read-only journal, a fresh render: exit $rc, stderr: $(head -c 300 "$d/err"), files: $(ls -A "$d" | tr '\n' ' ')"
fi

# ---- the files a scene writes ---------------------------------------------------------
sd=$T/scene_dir
rd=$T/render_dir
mkdir -p "$sd" "$rd"
cat >"$sd/w.pov" <<'POV'
#fopen F "data.txt" write
#write (F, "\"s\",", 1.5, ",", <1,2,3>, "\n")
#fclose F
#fopen F "data.txt" read
#read (F, S, R, V)
#fopen L "log.txt" append
#write (L, S, R, "\n")
#fclose L
sphere { V, R pigment { rgb 1 } }
POV
abs_bin=$(realpath "$BIN")
(cd "$sd" && "$abs_bin" check w.pov >/dev/null 2>"$rd/err")
rc=$?
[ $rc = 0 ] && [ "$(ls -A "$sd")" = w.pov ] && [ "$(ls -A "$rd")" = err ] &&
    ok "check of a scene that writes files: exit 0, no file written" ||
    ko "check of a scene that writes files: exit $rc, files: $(ls -A "$sd" "$rd" | tr '\n' ' ')"
for run in 1 2; do
    "$BIN" render "$sd/w.pov" "${SMALL[@]}" -o "$rd/o.png" >/dev/null 2>"$rd/err"
    rc=$?
done
[ $rc = 0 ] && [ "$(printf '"s",1.5,<1,2,3> \n')" = "$(cat "$rd/data.txt")" ] &&
    [ "$(printf 's1.5\ns1.5')" = "$(cat "$rd/log.txt")" ] && [ "$(ls -A "$sd")" = w.pov ] &&
    ok "render: the scene's files beside the output, POV-Ray's text, the appended one twice" ||
    ko "render of a scene that writes files: exit $rc, stderr: $(head -c 300 "$rd/err"), files: $(ls -A "$rd" | tr '\n' ' ')"
printf '#fopen F "o.png" write #write (F, 1) #fclose F sphere { 0, 1 }\n' >"$sd/clash.pov"
"$BIN" render "$sd/clash.pov" "${SMALL[@]}" -o "$rd/o.png" >/dev/null 2>"$rd/err"
rc=$?
[ $rc = 2 ] && grep -q "the scene writes 'o.png', which would replace $rd/o.png: refusing" "$rd/err" &&
    [ -s "$rd/o.png" ] && ok "a scene that writes the output's name: exit 2, refused" ||
    ko "a scene that writes the output's name: exit $rc, stderr: $(head -c 300 "$rd/err")"
rm -f "$rd/data.txt"
ln -s "$T/elsewhere.txt" "$rd/data.txt"
"$BIN" render "$sd/w.pov" "${SMALL[@]}" -o "$rd/o.png" >/dev/null 2>"$rd/err"
rc=$?
[ $rc = 1 ] && grep -q "is a symbolic link" "$rd/err" && [ -L "$rd/data.txt" ] &&
    [ ! -e "$T/elsewhere.txt" ] && ok "a symbolic link at a written file's name: exit 1, kept" ||
    ko "a symbolic link at a written file's name: exit $rc, stderr: $(head -c 300 "$rd/err")"
printf 'sphere { 0, 1 }\n#fopen F "../up.txt" write\n' >"$sd/up.pov"
"$BIN" render "$sd/up.pov" "${SMALL[@]}" -o "$rd/o.png" >/dev/null 2>"$rd/err"
rc=$?
[ $rc = 2 ] && grep -q "^$sd/up.pov:2:10: error: '../up.txt' leaves the scene's folder" "$rd/err" &&
    [ ! -e "$T/up.txt" ] && ok "a written name with '..': exit 2, an error at the name" ||
    ko "a written name with '..': exit $rc, stderr: $(head -c 300 "$rd/err")"

e2e_finish
