#!/bin/bash
# The simulated points of bench/PAGING.md, *Pages read one-sided*: the
# costs are calibration.csv's medians (4 rounds, serial 4096x4096, tile 64);
# the traces and maps are bench/results-paging/sim-4096's.  make sim first.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$(dirname "$0")/../../../.."
set -u
D=bench/results-paging/sim-4096; OUT=${OUT:-/tmp/sim-one-sided}; mkdir -p $OUT
echo "workers,mode,budget,fetch,homes,install_ns,pack_ns,efficiency,master_busy,faults,requests,bytes,wait_s,asks" > $OUT/points.csv
run() { # W MODE FRAC FETCH [INSTALL]
 local w=$1 mode=$2 frac=$3 fetch=$4 mb=1.310774 inst pack
 if [ $frac = 32 ]; then pack=0.196; [ $fetch = get ] && inst=1.263 || inst=1.477; else mb=5.243096; pack=0.185; [ $fetch = get ] && inst=1.093 || inst=1.409; fi
 [ -n "${5:-}" ] && inst=$5
 extra=(); [ $mode = hetero ] && extra=(--pass-rate 300 --fill-map $D/homo.costs)
 bench/simulate.sh build/bench/tetra9.nff --workers $w --mode $mode --network ib --size 4096x4096 --tile 64 --map $D/$mode.costs --schedule region "${extra[@]}" --scene-memory $mb --page-size 16 --page-trace $D/homo-1_$frac.trace.0:$D/hetero.trace.1 --page-install-ns $inst --master-page-ns $pack --page-fetch $fetch --stats $OUT/s.json > /dev/null 2>$OUT/err || { echo "$w,$mode,1/$frac,$fetch,failed" >> $OUT/points.csv; return; }
 python3 -c "
import json; d=json.load(open('$OUT/s.json')); p=d['paging']; m=d['scene_memory']
print(','.join(str(x) for x in [$w,'$mode','1/$frac',m['fetch'],m['homes'],$inst,$pack,d['efficiency'],d['master_busy'],p['faults'],p['requests'],p['bytes'],p['wait_s'],m['asks_answered']]))" >> $OUT/points.csv
}
for frac in 32 8; do for mode in homo hetero; do for fetch in get ask; do run 64 $mode $frac $fetch; done; done; done
run 64 homo 32 get 0
for w in 16 256; do for mode in homo hetero; do for fetch in get ask; do run $w $mode 32 $fetch; done; done; done
echo done >> $OUT/points.csv
