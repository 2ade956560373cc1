#!/bin/bash
# bench/node_memory.sh — the node's memory of one render: the sum of its
# ranks' PSS (proportional set size: a page shared by n processes counts
# 1/n in each, so the sum counts the node's one copy of the scene once).
#
#   bench/node_memory.sh RANKS csgtrace render SCENE -o OUT [options…]
#
# Runs the command under mpirun -np RANKS (--bind-to none, the variables
# tests/run.sh sets), reads /proc/PID/smaps_rollup of every csgtrace child
# of mpirun every 0.2 s, and prints two lines: the sample where the sum
# was largest (rank 0's parse is then often all of it), and the one where
# the workers' sum was (the tile phase: every rank holds the scene); then
# each rank's largest PSS over the run:
#   peak: ranks=N sum_pss_mib=M sum_shmem_mib=S rank0_mib=A workers_mean_mib=B
#   tiles: (the same fields)
#   rank R: pss_mib=P (shmem S, anon A)
# sum_shmem is the PSS of shared memory (the node's copy of the scene, and
# Open MPI's own segments); rank 0's PSS includes what the parse keeps.
set -u
ranks=$1
shift
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1 \
    OMPI_MCA_rmaps_base_oversubscribe=1
mpirun -np "$ranks" --bind-to none "$@" >/dev/null &
top=$!
best_sum=0 best_line="" best_wsum=-1 tiles_line=""
declare -A peak peak_shm peak_anon rank
while kill -0 "$top" 2>/dev/null; do
    sum=0 shm=0 r0=0 wsum=0 wn=0
    for pid in $(pgrep -P "$top" -x csgtrace); do
        roll=$(cat "/proc/$pid/smaps_rollup" 2>/dev/null) || continue
        p=$(awk '/^Pss:/{print $2}' <<<"$roll")
        s=$(awk '/^Pss_Shmem:/{print $2}' <<<"$roll")
        a=$(awk '/^Pss_Anon:/{print $2}' <<<"$roll")
        [ -n "$p" ] || continue
        [ -n "${rank[$pid]:-}" ] || rank[$pid]=$(tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null |
            awk -F= '/^OMPI_COMM_WORLD_RANK=/{print $2}')
        sum=$((sum + p))
        shm=$((shm + ${s:-0}))
        if [ "${rank[$pid]}" = 0 ]; then r0=$p; else wsum=$((wsum + p)); wn=$((wn + 1)); fi
        if [ "${peak[$pid]:-0}" -lt "$p" ]; then
            peak[$pid]=$p peak_shm[$pid]=${s:-0} peak_anon[$pid]=${a:-0}
        fi
    done
    line=$(awk -v n="$ranks" -v s="$sum" -v h="$shm" -v r="$r0" -v w="$wsum" -v k="$wn" \
        'BEGIN { printf "ranks=%d sum_pss_mib=%.1f sum_shmem_mib=%.1f rank0_mib=%.1f workers_mean_mib=%.1f",
                 n, s / 1024, h / 1024, r / 1024, k ? w / k / 1024 : 0 }')
    if [ "$sum" -gt "$best_sum" ]; then
        best_sum=$sum best_line=$line
    fi
    if [ "$wsum" -gt "$best_wsum" ]; then
        best_wsum=$wsum tiles_line=$line
    fi
    sleep 0.2
done
wait "$top"
rc=$?
echo "peak:  $best_line rc=$rc"
echo "tiles: $tiles_line"
for pid in "${!peak[@]}"; do
    awk -v r="${rank[$pid]}" -v p="${peak[$pid]}" -v s="${peak_shm[$pid]}" -v a="${peak_anon[$pid]}" \
        'BEGIN { printf "  rank %s: pss_mib=%.1f (shmem %.1f, anon %.1f)\n", r, p / 1024, s / 1024, a / 1024 }'
done | sort -k2n
