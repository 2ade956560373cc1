#!/bin/bash
# bench/memory_peak.sh — the peak memory of every rank of one render.
#
#   bench/memory_peak.sh RANKS csgtrace render SCENE -o OUT [options…]
#
# Runs the command (under mpirun -np RANKS when RANKS > 1, with the
# variables tests/run.sh sets and --bind-to none for PoCL), samples the
# /proc/PID/status of the command (or of mpirun's csgtrace children)
# every 0.1 s, and prints one line:
#   rank0_hwm_kib=N rank0_anon_kib=N workers_hwm_kib=N wall_s=S rc=R
# rank0_hwm is VmHWM (peak resident set: anonymous memory plus the pages
# of the mapped libraries, PoCL's and OpenImageIO's), rank0_anon the peak
# of RssAnon seen (the process's own allocations), workers_hwm the largest
# worker's VmHWM.  A peak shorter than the sampling period can be missed
# by rank0_anon, not by the VmHWM values (the kernel keeps them).
set -u
ranks=$1
shift
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1 \
    OMPI_MCA_rmaps_base_oversubscribe=1
if [ "$ranks" -gt 1 ]; then
    set -- mpirun -np "$ranks" --bind-to none "$@"
fi
t0=$(date +%s.%N)
"$@" >/dev/null &
top=$!
declare -A hwm anon rank
while kill -0 "$top" 2>/dev/null; do
    for pid in $(if [ "$ranks" -gt 1 ]; then pgrep -P "$top" -x csgtrace; else echo "$top"; fi); do
        s=$(cat "/proc/$pid/status" 2>/dev/null) || continue
        h=$(awk '/^VmHWM/{print $2}' <<<"$s")
        a=$(awk '/^RssAnon/{print $2}' <<<"$s")
        [ -n "$h" ] || continue
        [ -n "${rank[$pid]:-}" ] || rank[$pid]=$(tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null |
            awk -F= '/^OMPI_COMM_WORLD_RANK=/{print $2}')
        hwm[$pid]=$h
        [ "${anon[$pid]:-0}" -ge "$a" ] || anon[$pid]=$a
    done
    sleep 0.1
done
wait "$top"
rc=$?
t1=$(date +%s.%N)
r0_hwm=0 r0_anon=0 w_hwm=0
for pid in "${!hwm[@]}"; do
    if [ "${rank[$pid]:-0}" = 0 ]; then
        [ "${hwm[$pid]}" -le "$r0_hwm" ] || r0_hwm=${hwm[$pid]}
        [ "${anon[$pid]}" -le "$r0_anon" ] || r0_anon=${anon[$pid]}
    elif [ "${hwm[$pid]}" -gt "$w_hwm" ]; then
        w_hwm=${hwm[$pid]}
    fi
done
wall=$(echo "$t1 - $t0" | bc)
echo "rank0_hwm_kib=$r0_hwm rank0_anon_kib=$r0_anon workers_hwm_kib=$w_hwm wall_s=$wall rc=$rc"
