# armadillo-stvk: relative energy error against solve time
set terminal png size 1400,850 font 'DejaVu Sans,11' noenhanced
set output 'armadillo-stvk.png'
set title "armadillo-stvk: 54985 tets, stvk E=5e+07 nu=0.4, 1 step(s), median of 1\nfastest to 1e-04: pd-local-global (1.01x faster than lbfgs-pd5)"
left = 0.01  # the start point x0 (time 0) is drawn at the left edge
set xrange [left:*]
set logscale xy
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set format y '1e%L'
set format x '%g'
set xlabel 'solve time (s) of each step, median of the timed repeats'
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set yrange [1e-06:3]
set key outside right top spacing 1.1
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt 3
set arrow from graph 0, first 0.001 to graph 1, first 0.001 nohead lc rgb '#999999' dt 3
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt 3
plot \
  'armadillo-stvk.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 1 lw 2.5 pt 7 ps 0.4 title 'newton-clamp-backtracking (baseline)', \
  'armadillo-stvk.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-1it', \
  'armadillo-stvk.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-3it', \
  'armadillo-stvk.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#ff7f0e' dt 1 lw 1.5 pt 7 ps 0.4 title 'lbfgs-pd5', \
  'armadillo-stvk.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#9467bd' dt 1 lw 1.5 pt 7 ps 0.4 title 'lbfgs-pd5-10it', \
  'armadillo-stvk.dat' index 5 using ($1>0?$1:left):2 with linespoints lc rgb '#8c564b' dt 1 lw 3.5 pt 7 ps 0.4 title 'pd-local-global (fastest)', \
  'armadillo-stvk.dat' index 6 using ($1>0?$1:left):2 with linespoints lc rgb '#e377c2' dt 1 lw 1.5 pt 7 ps 0.4 title 'pd-local-global-aa5'
