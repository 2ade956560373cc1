#!/bin/bash
# interleaved A/B of two builds, tetra9 1024x1024, 2 workers: the walks' page test inline
# OLD=build NEW=build: two builds of csgtrace (here: main at 4a24fa3 and 439734b,
# before and after the walks' page test went inline); writes /tmp/abw/abw.csv
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1 OMPI_MCA_rmaps_base_oversubscribe=1
cd "$(dirname "$0")/../../.."; export POCL_CACHE_DIR=$PWD/build/pocl-cache CSGTRACE_CL_CACHE=$PWD/build/cl-cache
S=build/bench/tetra9.nff; C="--width 1024 --height 1024 --no-progress"; OUT=/tmp/abw; mkdir -p $OUT
: "${OLD:?OLD=path to the first build}" "${NEW:?NEW=path to the second build}"
echo "round,config,build,tile_phase_s,wait_s,install_s,identical" > $OUT/abw.csv
$NEW render $S $C -o $OUT/ref.png >/dev/null
for r in $(seq 1 ${RUNS:-7}); do
 for cfg in "mem-homo homo 0" "homo-32 homo 32" "hetero-32 hetero 32" "homo-8 homo 8"; do
  read -r name mode frac <<<"$cfg"
  for build in old new; do
   [ $frac = 0 ] && [ $build = old ] && continue
   B=$NEW; [ $build = old ] && B=$OLD
   a=(--mode $mode); [ $mode = hetero ] && a+=(--pass always --fill off)
   [ $frac != 0 ] && a+=(--scene-memory $(python3 -c "print(41944768/$frac/1e6)"))
   mpirun -np 3 --bind-to none $B render $S $C "${a[@]}" -o $OUT/o.png --stats $OUT/o.json >/dev/null 2>&1 || { echo "$r,$name,$build,failed" >> $OUT/abw.csv; continue; }
   same=no; cmp -s $OUT/ref.png $OUT/o.png && same=yes
   python3 -c "
import json; j=json.load(open('$OUT/o.json')); p=j.get('paging') or {}
print(','.join(str(x) for x in ['$r','$name','$build',j['tile_phase_s'],p.get('wait_s',0),p.get('install_s',0),'$same']))" >> $OUT/abw.csv
  done
 done
done; echo done >> $OUT/abw.csv
