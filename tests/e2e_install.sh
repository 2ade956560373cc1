#!/usr/bin/env bash
# e2e_install.sh — the program installed (make install PREFIX=...) works
# with nothing of the source tree: the installed binary, its image module
# (PREFIX/lib/csgtrace/) and its manual page; run from another folder with
# the checkout hidden (a private mount namespace binds an empty folder over
# it), it renders the showcase in hetero mode (the OpenCL source is in the
# binary) and to TIFF (the module), both the images of the build tree's
# program; the manual page names every option --help does.
# Usage: tests/e2e_install.sh   (run as root: unshare -m)
set -u
source "$(dirname "$0")/lib_e2e.sh"
mpi_sandbox
ROOT=$(pwd)
P=$T/prefix

if make -s install PREFIX="$P" >"$T/install.log" 2>&1 &&
    [ -x "$P/bin/csgtrace" ] && [ -f "$P/lib/csgtrace/csgtrace-image.so" ] &&
    [ -f "$P/share/man/man1/csgtrace.1" ]; then
    ok "make install PREFIX=...: bin/csgtrace, lib/csgtrace/csgtrace-image.so, share/man/man1/csgtrace.1"
else
    ko "make install: $(tail -3 "$T/install.log")"
fi

missing=""
for opt in $("$BIN" --help | grep -o -- '--[a-z][a-z-]*' | sort -u); do
    grep -q -- "$(echo "$opt" | sed 's/-/\\\\-/g')" "$P/share/man/man1/csgtrace.1" || missing="$missing $opt"
done
[ -z "$missing" ] && ok "the manual page names every option of --help" ||
    ko "the manual page lacks:$missing"

"$P/bin/csgtrace" --version | grep -qE '^csgtrace [0-9.]+ \(build [0-9a-f]{16}\)$' &&
    ok "--version names the version and the build" || ko "--version: $("$P/bin/csgtrace" --version)"

# The references, by the build tree's program.
"$BIN" render scenes/showcase.pov -o "$T/ref.png" --width 160 --height 120 >/dev/null 2>&1 ||
    ko "reference render"
mkdir -p "$T/elsewhere" "$T/empty"
cp scenes/showcase.pov "$T/elsewhere/"
cat >"$T/elsewhere/run.sh" <<SH
set -e
mount --bind "$T/empty" "$ROOT"
[ -z "\$(ls -A "$ROOT")" ] # (the checkout hidden)
cd "$T/elsewhere"
export CSGTRACE_CL_CACHE=off
mpirun --oversubscribe --bind-to none -np 3 "$P/bin/csgtrace" render showcase.pov -o hetero.png \\
    --mode hetero --fill off --width 160 --height 120 --stats hetero.json
"$P/bin/csgtrace" render showcase.pov -o serial.tif --width 160 --height 120
SH
if unshare -m bash "$T/elsewhere/run.sh" >"$T/run.log" 2>&1; then
    cmp -s "$T/ref.png" "$T/elsewhere/hetero.png" &&
        json "$T/elsewhere/hetero.json" "j['slices'] > 0 and j['cl_program'] != ''" &&
        ok "installed, the checkout hidden: hetero (the OpenCL pass ran) == the build tree's PNG" ||
        ko "installed hetero render differs, or ran no pass"
    same "$T/ref.png" "$T/elsewhere/serial.tif" &&
        ok "installed, the checkout hidden: TIFF through the installed module, the same pixels" ||
        ko "installed TIFF render differs"
else
    ko "the installed program, the checkout hidden: $(tail -5 "$T/run.log")"
fi

make -s uninstall PREFIX="$P" >/dev/null 2>&1
[ -z "$(find "$P" -type f)" ] && ok "make uninstall removes every file it installed" ||
    ko "make uninstall left: $(find "$P" -type f | head -3)"

e2e_finish
