# plot_occ_sweep.gp — beyond the paper: the advantage vs occupancy 5-95 %
# (occ_sweep.dat: occ_target adv).
load bench.'/plot_common.gp'
set output 'occ_sweep.png'
set title "Advantage vs occupancy 5-95 % (30 spheres)"
set xlabel "occupancy target [%]"
plot 'occ_sweep.dat' using 1:2 with linespoints lw 2 title "ours"
