# cantilever-1e7-5k-fcr: relative energy error against solve time
set terminal png size 1400,850 font 'DejaVu Sans,11' noenhanced
set output 'cantilever-1e7-5k-fcr.png'
set title "cantilever-1e7-5k-fcr: 5000 tets, fixed_corotated E=1e+07 nu=0.3, 1 step(s), median of 3\nfastest to 1e-06: newton-clamp-backtracking (1.14x faster than newton-abs-backtracking)"
left = 0.001  # the start point x0 (time 0) is drawn at the left edge
set xrange [left:*]
set logscale xy
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set format y '1e%L'
set format x '%g'
set xlabel 'solve time (s) of each step, median of the timed repeats'
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set yrange [1e-11:3]
set key outside right top spacing 1.1
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt 3
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt 3
set arrow from graph 0, first 1e-06 to graph 1, first 1e-06 nohead lc rgb '#999999' dt 3
set arrow from graph 0, first 1e-08 to graph 1, first 1e-08 nohead lc rgb '#999999' dt 3
plot \
  'cantilever-1e7-5k-fcr.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 1 lw 3.5 pt 7 ps 0.4 title 'newton-clamp-backtracking (baseline) (fastest)', \
  'cantilever-1e7-5k-fcr.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-clamp-exact', \
  'cantilever-1e7-5k-fcr.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-clamp-none', \
  'cantilever-1e7-5k-fcr.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#ff7f0e' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-abs-backtracking', \
  'cantilever-1e7-5k-fcr.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#9467bd' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-abs-exact', \
  'cantilever-1e7-5k-fcr.dat' index 5 using ($1>0?$1:left):2 with linespoints lc rgb '#8c564b' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-abs-none', \
  'cantilever-1e7-5k-fcr.dat' index 6 using ($1>0?$1:left):2 with linespoints lc rgb '#e377c2' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-shift-backtracking', \
  'cantilever-1e7-5k-fcr.dat' index 7 using ($1>0?$1:left):2 with linespoints lc rgb '#17becf' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-shift-exact', \
  'cantilever-1e7-5k-fcr.dat' index 8 using ($1>0?$1:left):2 with linespoints lc rgb '#7f7f7f' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-shift-none', \
  'cantilever-1e7-5k-fcr.dat' index 9 using ($1>0?$1:left):2 with linespoints lc rgb '#bcbd22' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-none-backtracking', \
  'cantilever-1e7-5k-fcr.dat' index 10 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-none-exact', \
  'cantilever-1e7-5k-fcr.dat' index 11 using ($1>0?$1:left):2 with linespoints lc rgb '#aec7e8' dt 1 lw 1.5 pt 7 ps 0.4 title 'newton-none-none', \
  'cantilever-1e7-5k-fcr.dat' index 12 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 2 lw 1.5 pt 7 ps 0.4 title 'lbfgs-backtracking', \
  'cantilever-1e7-5k-fcr.dat' index 13 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 2 lw 1.5 pt 7 ps 0.4 title 'lbfgs-exact', \
  'cantilever-1e7-5k-fcr.dat' index 14 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 2 lw 1.5 pt 7 ps 0.4 title 'lbfgs-none', \
  'cantilever-1e7-5k-fcr.dat' index 15 using ($1>0?$1:left):2 with linespoints lc rgb '#ff7f0e' dt 2 lw 1.5 pt 7 ps 0.4 title 'gradient_descent-backtracking', \
  'cantilever-1e7-5k-fcr.dat' index 16 using ($1>0?$1:left):2 with linespoints lc rgb '#9467bd' dt 2 lw 1.5 pt 7 ps 0.4 title 'gradient_descent-exact', \
  'cantilever-1e7-5k-fcr.dat' index 17 using ($1>0?$1:left):2 with linespoints lc rgb '#8c564b' dt 2 lw 1.5 pt 7 ps 0.4 title 'gradient_descent-none', \
  'cantilever-1e7-5k-fcr.dat' index 18 using ($1>0?$1:left):2 with linespoints lc rgb '#e377c2' dt 2 lw 1.5 pt 7 ps 0.4 title 'nlopt-lbfgs', \
  'cantilever-1e7-5k-fcr.dat' index 19 using ($1>0?$1:left):2 with linespoints lc rgb '#17becf' dt 2 lw 1.5 pt 7 ps 0.4 title 'ipopt-clamp', \
  'cantilever-1e7-5k-fcr.dat' index 20 using ($1>0?$1:left):2 with linespoints lc rgb '#7f7f7f' dt 2 lw 1.5 pt 7 ps 0.4 title 'pd-backtracking', \
  'cantilever-1e7-5k-fcr.dat' index 21 using ($1>0?$1:left):2 with linespoints lc rgb '#bcbd22' dt 2 lw 1.5 pt 7 ps 0.4 title 'pd-lbfgs5-backtracking'
