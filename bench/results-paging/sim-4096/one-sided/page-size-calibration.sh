#!/bin/bash
# serial tetra9 4096x4096 tile 64 at 1/32, pages of 16/32/64 KiB, 3 rounds interleaved: the install per byte
# for the simulator, and (round 1) the page traces; writes /tmp/p64 (bench/PAGING.md, *The 64-worker point rerun*)
cd "$(dirname "$0")/../../../.."; S=build/bench/tetra9.nff
echo "round,page_kb,tile_phase_s,install_s,wait_s,bytes,faults,pages,identical" > /tmp/p64/cal.csv
build/csgtrace render $S --width 4096 --height 4096 --tile 64 --no-progress -o /tmp/p64/ref.png >/dev/null
for r in 1 2 3; do for ps in 16 32 64; do
  tr=(); [ $r = 1 ] && tr=(CSGTRACE_PAGE_TRACE=/tmp/p64/homo-1_32-p$ps.trace)
  env "${tr[@]}" build/csgtrace render $S --width 4096 --height 4096 --tile 64 --no-progress --scene-memory 1.310774 --page-size $ps -o /tmp/p64/o.png --stats /tmp/p64/o.json >/dev/null 2>&1
  same=no; cmp -s /tmp/p64/ref.png /tmp/p64/o.png && same=yes
  python3 -c "
import json; j=json.load(open('/tmp/p64/o.json')); p=j['paging']
print(','.join(str(x) for x in [$r,$ps,j['tile_phase_s'],p['install_s'],p['wait_s'],p['bytes'],p['faults'],p['pages'],'$same']))" >> /tmp/p64/cal.csv
done; done; echo done >> /tmp/p64/cal.csv
