# plot_big_objects.gp — beyond the paper: the advantage vs objects, log scale
# (big_objects.dat: count adv).
load bench.'/plot_common.gp'
set output 'big_objects.png'
set title "Advantage vs objects, beyond the paper (occupancy 50 %)"
set xlabel "objects (spheres, log scale)"
set logscale x
plot 'big_objects.dat' using 1:2 with linespoints lw 2 title "ours"
