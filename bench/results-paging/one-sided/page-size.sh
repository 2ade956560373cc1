#!/bin/bash
# page sizes under one-sided reads: tetra9 1024x1024 homo, 2 workers, 1/32 and 1/8, --page-size 16/32/64 KiB
# against in memory (config 0-32), RUNS rounds interleaved; writes /tmp/ps/ps.csv (bench/PAGING.md)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1 OMPI_MCA_rmaps_base_oversubscribe=1
cd "$(dirname "$0")/../../.."; export POCL_CACHE_DIR=$PWD/build/pocl-cache CSGTRACE_CL_CACHE=$PWD/build/cl-cache
S=build/bench/tetra9.nff; C="--width 1024 --height 1024 --no-progress"; OUT=/tmp/ps; mkdir -p $OUT
echo "round,config,tile_phase_s,wait_s,install_s,bytes,faults,identical" > $OUT/ps.csv
build/csgtrace render $S $C -o $OUT/ref.png >/dev/null
for r in $(seq 1 ${RUNS:-5}); do for ps in 0 16 32 64; do
  for frac in 32 8; do
  [ $ps = 0 ] && [ $frac = 8 ] && continue
  a=(--mode homo); [ $ps != 0 ] && a+=(--scene-memory $(python3 -c "print(41944768/$frac/1e6)") --page-size $ps)
  mpirun -np 3 --bind-to none build/csgtrace render $S $C "${a[@]}" -o $OUT/o.png --stats $OUT/o.json >/dev/null 2>&1 || { echo "$r,$ps,failed" >> $OUT/ps.csv; continue; }
  same=no; cmp -s $OUT/ref.png $OUT/o.png && same=yes
  python3 -c "
import json; j=json.load(open('$OUT/o.json')); p=j.get('paging') or {}
print(','.join(str(x) for x in ['$r','$ps-$frac',j['tile_phase_s'],p.get('wait_s',0),p.get('install_s',0),p.get('bytes',0),p.get('faults',0),'$same']))" >> $OUT/ps.csv
  done
done; done; echo done >> $OUT/ps.csv
