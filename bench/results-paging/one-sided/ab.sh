#!/bin/bash
# interleaved A/B: --page-fetch get against ask, tetra9 1024x1024, 1/32 and 1/8
# (bench/PAGING.md, *Pages read one-sided*); writes $OUT/ab.csv (default /tmp/ab).
# Another scene: S=scene BLOB=its blob's bytes (stats: blob_bytes) RUNS=n CONFIGS=...
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1 OMPI_MCA_rmaps_base_oversubscribe=1
cd "$(dirname "$0")/../../.."
export POCL_CACHE_DIR=$PWD/build/pocl-cache CSGTRACE_CL_CACHE=$PWD/build/cl-cache
B=${B:-build/csgtrace}; S=${S:-build/bench/tetra9.nff}; C="--width ${SIZE:-1024} --height ${SIZE:-1024} --no-progress"
BLOB=${BLOB:-41944768}; OUT=${OUT:-/tmp/ab}; mkdir -p $OUT
echo "round,config,tile_phase_s,wall_s,wait_s,install_s,faults,requests,master_cpu,identical" > $OUT/ab.csv
$B render $S $C -o $OUT/ref.png >/dev/null
# CONFIGS: "name mode fraction fetch" rows, separated by commas (fraction 0: in memory)
CONFIGS=${CONFIGS:-"mem-homo homo 0 get,mem-hetero hetero 0 get,homo-get-32 homo 32 get,homo-ask-32 homo 32 ask,hetero-get-32 hetero 32 get,hetero-ask-32 hetero 32 ask,homo-get-8 homo 8 get,homo-ask-8 homo 8 ask,hetero-get-8 hetero 8 get,hetero-ask-8 hetero 8 ask"}
IFS=, read -r -a configs <<<"$CONFIGS"
for r in $(seq 1 ${RUNS:-7}); do
 for cfg in "${configs[@]}"; do
  read -r name mode frac fetch <<<"$cfg"
  args=(--mode $mode); [ $mode = hetero ] && args+=(--pass always --fill off)
  [ $frac != 0 ] && args+=(--scene-memory $(python3 -c "print($BLOB/$frac/1e6)") --page-fetch $fetch)
  mpirun -np 3 --bind-to none $B render $S $C "${args[@]}" -o $OUT/o.png --stats $OUT/o.json >/dev/null 2>$OUT/err || { echo "$r,$name,failed" >> $OUT/ab.csv; continue; }
  same=no; cmp -s $OUT/ref.png $OUT/o.png && same=yes
  python3 -c "
import json,sys
j=json.load(open('$OUT/o.json')); p=j.get('paging',{})
print(','.join(str(x) for x in ['$r','$name',j['tile_phase_s'],j['wall_s'],p.get('wait_s',0),p.get('install_s',0),p.get('faults',0),p.get('requests',0),j.get('master_cpu_s',''),'$same']))" >> $OUT/ab.csv
 done
done
echo done >> $OUT/ab.csv
