# plot_beyond.gp — beyond the paper: the advantage vs objects (log scale), image
# size and occupancy 5-95 %, one PNG each (big_objects.dat, big_size.dat,
# occ_sweep.dat: x adv).
load bench.'/plot_common.gp'
set output 'big_objects.png'
set title "Advantage vs objects, beyond the paper (occupancy 50 %)"
set xlabel "objects (spheres, log scale)"
set logscale x
plot 'big_objects.dat' using 1:2 with linespoints lw 2 title "ours"
unset logscale x
set output 'big_size.png'
set title "Advantage vs image size, beyond the paper (30 spheres, occupancy 50 %)"
set xlabel "image size [pixels, square]"
plot 'big_size.dat' using 1:2 with linespoints lw 2 title "ours"
set output 'occ_sweep.png'
set title "Advantage vs occupancy 5-95 % (30 spheres)"
set xlabel "occupancy target [%]"
plot 'occ_sweep.dat' using 1:2 with linespoints lw 2 title "ours"
