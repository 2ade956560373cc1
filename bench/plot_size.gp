# plot_size.gp — Figure 3: the advantage vs image size, averaged over objects and
# occupancies (size.dat: size adv), and the paper's endpoints.
load bench.'/plot_common.gp'
set output 'size.png'
set title "Advantage vs image size (mean over objects and occupancies) — cf. Figure 3"
set xlabel "image size [pixels, square]"
set print $paper
print "x paper"
print "192 11"
print "384 17"
unset print
plot 'size.dat' using 1:2 with linespoints lw 2 title "ours", \
     $paper using 1:2 with linespoints dt 2 lc rgb "gray40" title "paper (endpoints)"
