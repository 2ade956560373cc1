# plot_scale.gp — simulated parallel efficiency at 4096x4096, the best tile
# per point (scale_eff.dat: workers ib_homo ib_hetero gige_homo gige_hetero).
load bench.'/plot_common.gp'
set datafile columnheaders
set output 'scale_efficiency.png'
set title "Simulated efficiency, 4096x4096, best tile per point"
set xlabel "workers [log scale]"
set ylabel "efficiency = serial_s / (workers x makespan_s)"
set logscale x 2
set yrange [0:1.05]
set datafile missing "nan"
plot 'scale_eff.dat' using 1:2 with linespoints lw 2 title "InfiniBand, homo (raster)", \
     'scale_eff.dat' using 1:3 with linespoints lw 2 title "InfiniBand, hetero (cost)", \
     'scale_eff.dat' using 1:4 with linespoints lw 2 title "GigE, homo (raster)", \
     'scale_eff.dat' using 1:5 with linespoints lw 2 title "GigE, hetero (cost)"
