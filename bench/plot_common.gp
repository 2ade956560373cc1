# plot_common.gp — shared settings, loaded by the plot_*.gp scripts (run from
# the results folder with -e "term='pngcairo'; bench='/path/to/bench'").
if (!exists("term")) term = 'pngcairo'
if (term eq 'pngcairo') set terminal pngcairo size 800,500 font ",11"; else set terminal png size 800,500
set grid
set key below
set termoption noenhanced
set datafile columnheaders
set ylabel "heterogeneous advantage (homo - hetero) / homo  [%]"
