# bunny-pdvol: relative energy error against solve time, one panel per measured step
# colour = optimizer family (baseline black), dash = line search, point = Hessian fix;
# in colour: the baseline, the fastest and the best of each family (at most 8)
if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1827,740 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1827,740 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'bunny-pdvol.png'
left = 0.01  # the start point x0 (time 0) is drawn at the left edge
stats 'bunny-pdvol.dat' using 1 nooutput
right = STATS_max > left ? 10**ceil(log10(STATS_max)) : 10*left
set xrange [left:right]
set yrange [1e-06:3]
set logscale xy
set grid xtics ytics lc rgb '#d8d8d8'
set mxtics 10
set mytics 10
set format y '1e%L'
set format x '%g'
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt (4,4) front
set label '1e-2' at graph 1, first 0.01 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 0.001 to graph 1, first 0.001 nohead lc rgb '#999999' dt (4,4) front
set label '1e-3' at graph 1, first 0.001 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt (4,4) front
set label '1e-4' at graph 1, first 0.0001 offset char 0.4,0 left font ',8' tc rgb '#777777'
set key at screen 0.7553, screen 0.8919 left top Left reverse box opaque samplen 4 spacing 1.1 font ',10'
set multiplot title "bunny-pdvol: 19379 tets, pd_volume E=1e+06 nu=0.4; 2 measured steps, median of 1 repeat\nfastest to 1e-4 (time summed over the 2 steps): newton-clamp-backtracking, 4.08x faster than the next, pd-local-global-aa5" font ',12'

# panel 1: measured step 2
set lmargin at screen 0.0493
set rmargin at screen 0.3777
set tmargin at screen 0.8919
set bmargin at screen 0.0811
set title 'step 2 (t = 0.06667 s)' offset 0,-0.4
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set format y '1e%L'
set xlabel 'solve time of the step (s); median of the repeats; x0 at the left edge'
plot \
  'bunny-pdvol.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 3.0 pt 7 ps 0.8 pi 1 title 'newton-clamp-backtracking (baseline) (fastest)', \
  'bunny-pdvol.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 1 lw 1.6 pt 5 ps 0.8 pi 1 title 'lbfgs-pd5', \
  'bunny-pdvol.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 1 lw 1.6 pt 9 ps 0.8 pi 8 title 'pd-local-global', \
  'bunny-pdvol.dat' index 6 using ($1>0?$1:left):2 with linespoints lc rgb '#185818' dt 1 lw 1.6 pt 9 ps 0.8 pi 1 title 'pd-local-global-aa5', \
  keyentry with lines lc rgb '#ffffff' title 'line style = line search:', \
  keyentry with lines lc rgb '#555555' lw 1.8 dt 1 title '  backtracking', \
  keyentry with lines lc rgb '#ffffff' title 'point = Hessian fix:', \
  keyentry with points lc rgb '#555555' pt 7 ps 1.0 title '  clamp', \
  keyentry with points lc rgb '#555555' pt 5 ps 1.0 title '  project_on_demand', \
  keyentry with points lc rgb '#555555' pt 9 ps 1.0 title '  (no Hessian)'

# panel 2: measured step 3
set lmargin at screen 0.3996
set rmargin at screen 0.7280
set tmargin at screen 0.8919
set bmargin at screen 0.0811
set title 'step 3 (t = 0.1 s)' offset 0,-0.4
set ylabel ''
set format y ''
set xlabel 'solve time of the step (s); median of the repeats; x0 at the left edge'
unset key
plot \
  'bunny-pdvol.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 3.0 pt 7 ps 0.8 pi 1 title 'newton-clamp-backtracking (baseline) (fastest)', \
  'bunny-pdvol.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 1 lw 1.6 pt 5 ps 0.8 pi 2 title 'lbfgs-pd5', \
  'bunny-pdvol.dat' index 5 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 1 lw 1.6 pt 9 ps 0.8 pi 8 title 'pd-local-global', \
  'bunny-pdvol.dat' index 7 using ($1>0?$1:left):2 with linespoints lc rgb '#185818' dt 1 lw 1.6 pt 9 ps 0.8 pi 1 title 'pd-local-global-aa5'
unset multiplot

# ---- the same figure as SVG
reset
set terminal svg size 1827,740 font 'DejaVu Sans,10' noenhanced
set output 'bunny-pdvol.svg'
left = 0.01  # the start point x0 (time 0) is drawn at the left edge
stats 'bunny-pdvol.dat' using 1 nooutput
right = STATS_max > left ? 10**ceil(log10(STATS_max)) : 10*left
set xrange [left:right]
set yrange [1e-06:3]
set logscale xy
set grid xtics ytics lc rgb '#d8d8d8'
set mxtics 10
set mytics 10
set format y '1e%L'
set format x '%g'
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt (4,4) front
set label '1e-2' at graph 1, first 0.01 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 0.001 to graph 1, first 0.001 nohead lc rgb '#999999' dt (4,4) front
set label '1e-3' at graph 1, first 0.001 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt (4,4) front
set label '1e-4' at graph 1, first 0.0001 offset char 0.4,0 left font ',8' tc rgb '#777777'
set key at screen 0.7553, screen 0.8919 left top Left reverse box opaque samplen 4 spacing 1.1 font ',10'
set multiplot title "bunny-pdvol: 19379 tets, pd_volume E=1e+06 nu=0.4; 2 measured steps, median of 1 repeat\nfastest to 1e-4 (time summed over the 2 steps): newton-clamp-backtracking, 4.08x faster than the next, pd-local-global-aa5" font ',12'

# panel 1: measured step 2
set lmargin at screen 0.0493
set rmargin at screen 0.3777
set tmargin at screen 0.8919
set bmargin at screen 0.0811
set title 'step 2 (t = 0.06667 s)' offset 0,-0.4
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set format y '1e%L'
set xlabel 'solve time of the step (s); median of the repeats; x0 at the left edge'
plot \
  'bunny-pdvol.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 3.0 pt 7 ps 0.8 pi 1 title 'newton-clamp-backtracking (baseline) (fastest)', \
  'bunny-pdvol.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 1 lw 1.6 pt 5 ps 0.8 pi 1 title 'lbfgs-pd5', \
  'bunny-pdvol.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 1 lw 1.6 pt 9 ps 0.8 pi 8 title 'pd-local-global', \
  'bunny-pdvol.dat' index 6 using ($1>0?$1:left):2 with linespoints lc rgb '#185818' dt 1 lw 1.6 pt 9 ps 0.8 pi 1 title 'pd-local-global-aa5', \
  keyentry with lines lc rgb '#ffffff' title 'line style = line search:', \
  keyentry with lines lc rgb '#555555' lw 1.8 dt 1 title '  backtracking', \
  keyentry with lines lc rgb '#ffffff' title 'point = Hessian fix:', \
  keyentry with points lc rgb '#555555' pt 7 ps 1.0 title '  clamp', \
  keyentry with points lc rgb '#555555' pt 5 ps 1.0 title '  project_on_demand', \
  keyentry with points lc rgb '#555555' pt 9 ps 1.0 title '  (no Hessian)'

# panel 2: measured step 3
set lmargin at screen 0.3996
set rmargin at screen 0.7280
set tmargin at screen 0.8919
set bmargin at screen 0.0811
set title 'step 3 (t = 0.1 s)' offset 0,-0.4
set ylabel ''
set format y ''
set xlabel 'solve time of the step (s); median of the repeats; x0 at the left edge'
unset key
plot \
  'bunny-pdvol.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 3.0 pt 7 ps 0.8 pi 1 title 'newton-clamp-backtracking (baseline) (fastest)', \
  'bunny-pdvol.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#d62728' dt 1 lw 1.6 pt 5 ps 0.8 pi 2 title 'lbfgs-pd5', \
  'bunny-pdvol.dat' index 5 using ($1>0?$1:left):2 with linespoints lc rgb '#2ca02c' dt 1 lw 1.6 pt 9 ps 0.8 pi 8 title 'pd-local-global', \
  'bunny-pdvol.dat' index 7 using ($1>0?$1:left):2 with linespoints lc rgb '#185818' dt 1 lw 1.6 pt 9 ps 0.8 pi 1 title 'pd-local-global-aa5'
unset multiplot
