# plot_scale_tile.gp — simulated makespan against the tile size, 4096x4096,
# homo raster (scale_tile.dat: tile, then one column per network x workers).
load bench.'/plot_common.gp'
set output 'scale_tile.png'
set title "Simulated makespan vs tile size, 4096x4096, homo (raster)"
set xlabel "tile size [pixels, log scale]"
set ylabel "makespan [s, log scale]"
set logscale x 2
set logscale y
set datafile missing "nan"
plot for [c=2:9] 'scale_tile.dat' using 1:c with linespoints lw 2 title columnheader(c)
