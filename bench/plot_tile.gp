# plot_tile.gp — the tile-size sweep: median time per mode vs tile size
# (tile.dat: tile homo_s hetero_s adv).
load bench.'/plot_common.gp'
set output 'tile.png'
set title "Tile size sweep (30 spheres, occupancy 50 %)"
set xlabel "tile size [pixels, log scale]"
set ylabel "median time (wall_s - compile_s) [s]"
set logscale x 2
plot 'tile.dat' using 1:2 with linespoints lw 2 title "homo", \
     'tile.dat' using 1:3 with linespoints lw 2 title "hetero"
