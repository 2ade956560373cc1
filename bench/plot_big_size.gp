# plot_big_size.gp — beyond the paper: the advantage vs image size
# (big_size.dat: width adv).
load bench.'/plot_common.gp'
set output 'big_size.png'
set title "Advantage vs image size, beyond the paper (30 spheres, occupancy 50 %)"
set xlabel "image size [pixels, square]"
plot 'big_size.dat' using 1:2 with linespoints lw 2 title "ours"
