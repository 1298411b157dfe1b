# inverted-start: relative energy error against solve time
# colour = optimizer family (baseline black), dash = line search, point = Hessian fix;
# in colour: the baseline, the fastest and the best of each family (at most 8)
set terminal png size 1400,850 font 'DejaVu Sans,11' noenhanced
set output 'inverted-start.png'
set title "inverted-start: 320 tets, stable_neo_hookean E=100000 nu=0.3, 2 step(s), median of 2\nfastest to 1e-06: pd-lbfgs5-backtracking (1.06x faster than pd_local_global-anderson)"
left = 1e-05  # the start point x0 (time 0) is drawn at the left edge
set xrange [left:*]
set logscale xy
set grid xtics ytics mxtics mytics lc rgb '#e5e5e5'
set format y '1e%L'
set format x '%g'
set xlabel 'solve time of the step (s), median of the timed repeats'
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set yrange [1e-11:3]
set key inside left bottom opaque box spacing 1.05 font ',10'
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt 3
set label '1e-02' at graph 1, first 0.01 offset char 0.5,0 left font ',9' tc rgb '#777777'
set arrow from graph 0, first 0.001 to graph 1, first 0.001 nohead lc rgb '#999999' dt 3
set label '1e-03' at graph 1, first 0.001 offset char 0.5,0 left font ',9' tc rgb '#777777'
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt 3
set label '1e-04' at graph 1, first 0.0001 offset char 0.5,0 left font ',9' tc rgb '#777777'
set arrow from graph 0, first 1e-06 to graph 1, first 1e-06 nohead lc rgb '#999999' dt 3
set label '1e-06' at graph 1, first 1e-06 offset char 0.5,0 left font ',9' tc rgb '#777777'
set arrow from graph 0, first 1e-08 to graph 1, first 1e-08 nohead lc rgb '#999999' dt 3
set label '1e-08' at graph 1, first 1e-08 offset char 0.5,0 left font ',9' tc rgb '#777777'
set rmargin 8
plot \
  'inverted-start.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 title '22 other configurations', \
  'inverted-start.dat' index 5 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 6 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 7 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 8 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 9 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 10 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 11 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 12 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 13 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 14 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 15 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 16 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 17 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 18 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 19 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 20 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 21 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 22 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 23 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 24 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 25 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 26 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 27 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 28 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 29 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 30 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 31 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 32 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 33 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 34 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 35 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 36 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 37 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 38 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 39 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 40 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 41 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 42 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 43 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 44 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 45 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 56 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 57 using ($1>0?$1:left):2 with linespoints lc rgb '#c8c8c8' dt 1 lw 0.8 pt 7 ps 0.2 notitle, \
  'inverted-start.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 2.4 pt 7 ps 0.6 title 'newton-clamp-backtracking (baseline)', \
  'inverted-start.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 2.4 pt 7 ps 0.6 notitle, \
  'inverted-start.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 2 lw 1.8 pt 7 ps 0.6 title 'newton-clamp-exact', \
  'inverted-start.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 2 lw 1.8 pt 7 ps 0.6 notitle, \
  'inverted-start.dat' index 46 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 5 lw 1.8 pt 13 ps 0.6 title 'lbfgs-wolfe', \
  'inverted-start.dat' index 47 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 5 lw 1.8 pt 13 ps 0.6 notitle, \
  'inverted-start.dat' index 48 using ($1>0?$1:left):2 with linespoints lc rgb '#9467bd' dt 5 lw 1.8 pt 13 ps 0.6 title 'ncg-wolfe', \
  'inverted-start.dat' index 49 using ($1>0?$1:left):2 with linespoints lc rgb '#9467bd' dt 5 lw 1.8 pt 13 ps 0.6 notitle, \
  'inverted-start.dat' index 50 using ($1>0?$1:left):2 with linespoints lc rgb '#8c564b' dt 1 lw 1.8 pt 13 ps 0.6 title 'pd_local_global-anderson', \
  'inverted-start.dat' index 51 using ($1>0?$1:left):2 with linespoints lc rgb '#8c564b' dt 1 lw 1.8 pt 13 ps 0.6 notitle, \
  'inverted-start.dat' index 52 using ($1>0?$1:left):2 with linespoints lc rgb '#e377c2' dt 1 lw 1.8 pt 13 ps 0.6 title 'nlopt-lbfgs', \
  'inverted-start.dat' index 53 using ($1>0?$1:left):2 with linespoints lc rgb '#e377c2' dt 1 lw 1.8 pt 13 ps 0.6 notitle, \
  'inverted-start.dat' index 54 using ($1>0?$1:left):2 with linespoints lc rgb '#17becf' dt 1 lw 1.8 pt 7 ps 0.6 title 'ipopt-clamp', \
  'inverted-start.dat' index 55 using ($1>0?$1:left):2 with linespoints lc rgb '#17becf' dt 1 lw 1.8 pt 7 ps 0.6 notitle, \
  'inverted-start.dat' index 58 using ($1>0?$1:left):2 with linespoints lc rgb '#bcbd22' dt 1 lw 3.2 pt 7 ps 0.6 title 'pd-lbfgs5-backtracking (fastest)', \
  'inverted-start.dat' index 59 using ($1>0?$1:left):2 with linespoints lc rgb '#bcbd22' dt 1 lw 3.2 pt 7 ps 0.6 notitle
set terminal svg size 1400,850 font 'DejaVu Sans,11' noenhanced
set output 'inverted-start.svg'
replot

