# plot_objects.gp — Figure 1: the advantage vs the number of objects, one line per
# occupancy (objects.dat: count occ20 occ50 occ80), and the paper's endpoints.
load bench.'/plot_common.gp'
set output 'objects.png'
set title "Advantage vs objects (384x384) — cf. the paper's Figure 1"
set xlabel "objects (spheres)"
set print $paper
print "x paper"
print "10 10"
print "50 23"
unset print
stats 'objects.dat' nooutput
plot for [i=2:STATS_columns] 'objects.dat' using 1:i with linespoints lw 2 \
         title columnhead(i), \
     $paper using 1:2 with linespoints dt 2 lc rgb "gray40" title "paper (endpoints)"
