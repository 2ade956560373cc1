# plot_occupancy.gp — Figure 2: the advantage vs occupancy, averaged over objects
# (occupancy.dat: occ adv), and the paper's endpoints.
load bench.'/plot_common.gp'
set output 'occupancy.png'
set title "Advantage vs occupancy (384x384, mean over 10-50 objects) — cf. Figure 2"
set xlabel "occupancy target [%]"
set print $paper
print "x paper"
print "20 17"
print "80 12"
unset print
plot 'occupancy.dat' using 1:2 with linespoints lw 2 title "ours", \
     $paper using 1:2 with linespoints dt 2 lc rgb "gray40" title "paper (endpoints)"
