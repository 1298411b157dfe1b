# bar-twist-p2-nu0.45: relative energy error against solve time, one panel per measured step
# colour = optimizer family (baseline black), dash = line search, point = Hessian fix;
# in colour: the baseline, the fastest and the best of each family (at most 8)
if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1420,800 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1420,800 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'bar-twist-p2-nu0.45.png'
left = 0.01  # the start point x0 (time 0) is drawn at the left edge
stats 'bar-twist-p2-nu0.45.dat' using 1 nooutput
right = STATS_max > left ? 10**ceil(log10(STATS_max)) : 10*left
set xrange [left:right]
set yrange [1e-11:3]
set logscale xy
set grid xtics ytics lc rgb '#d8d8d8'
set mxtics 10
set mytics 10
set format y '1e%L'
set format x '%g'
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt (4,4) front
set label '1e-2' at graph 1, first 0.01 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt (4,4) front
set label '1e-4' at graph 1, first 0.0001 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 1e-06 to graph 1, first 1e-06 nohead lc rgb '#999999' dt (4,4) front
set label '1e-6' at graph 1, first 1e-06 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 1e-08 to graph 1, first 1e-08 nohead lc rgb '#999999' dt (4,4) front
set label '1e-8' at graph 1, first 1e-08 offset char 0.4,0 left font ',8' tc rgb '#777777'
set key at screen 0.7606, screen 0.9000 left top Left reverse box opaque samplen 4 spacing 1.1 font ',10'
set multiplot title "bar-twist-p2-nu0.45: 2523 tets, stable_neo_hookean E=1e+06 nu=0.45; 1 measured step, median of 3 repeats\nfastest to 1e-6: newton-clamp, 1.13x faster than the next, newton-project_on_demand" font ',12'

# panel 1: measured step 6
set lmargin at screen 0.0634
set rmargin at screen 0.7254
set tmargin at screen 0.9000
set bmargin at screen 0.0750
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set format y '1e%L'
set xlabel 'solve time of the step (s); median of the repeats; x0 at the left edge'
plot \
  'bar-twist-p2-nu0.45.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 3.0 pt 7 ps 0.8 pi 1 title 'newton-clamp (baseline) (fastest)', \
  'bar-twist-p2-nu0.45.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 1 lw 1.6 pt 5 ps 0.8 pi 1 title 'newton-abs', \
  'bar-twist-p2-nu0.45.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#114163' dt 1 lw 1.6 pt 9 ps 0.8 pi 1 title 'newton-project_on_demand', \
  'bar-twist-p2-nu0.45.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#8fbbd9' dt 1 lw 1.6 pt 11 ps 0.8 pi 1 title 'newton-progressive', \
  'bar-twist-p2-nu0.45.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 1 lw 1.6 pt 13 ps 0.8 pi 1 title 'newton-trust_region_filter', \
  keyentry with lines lc rgb '#ffffff' title 'line style = line search:', \
  keyentry with lines lc rgb '#555555' lw 1.8 dt 1 title '  backtracking', \
  keyentry with lines lc rgb '#ffffff' title 'point = Hessian fix:', \
  keyentry with points lc rgb '#555555' pt 7 ps 1.0 title '  clamp', \
  keyentry with points lc rgb '#555555' pt 5 ps 1.0 title '  abs', \
  keyentry with points lc rgb '#555555' pt 9 ps 1.0 title '  project_on_demand', \
  keyentry with points lc rgb '#555555' pt 11 ps 1.0 title '  progressive', \
  keyentry with points lc rgb '#555555' pt 13 ps 1.0 title '  trust_region_filter'
unset multiplot

# ---- the same figure as SVG
reset
set terminal svg size 1420,800 font 'DejaVu Sans,10' noenhanced
set output 'bar-twist-p2-nu0.45.svg'
left = 0.01  # the start point x0 (time 0) is drawn at the left edge
stats 'bar-twist-p2-nu0.45.dat' using 1 nooutput
right = STATS_max > left ? 10**ceil(log10(STATS_max)) : 10*left
set xrange [left:right]
set yrange [1e-11:3]
set logscale xy
set grid xtics ytics lc rgb '#d8d8d8'
set mxtics 10
set mytics 10
set format y '1e%L'
set format x '%g'
set arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead lc rgb '#999999' dt (4,4) front
set label '1e-2' at graph 1, first 0.01 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 0.0001 to graph 1, first 0.0001 nohead lc rgb '#999999' dt (4,4) front
set label '1e-4' at graph 1, first 0.0001 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 1e-06 to graph 1, first 1e-06 nohead lc rgb '#999999' dt (4,4) front
set label '1e-6' at graph 1, first 1e-06 offset char 0.4,0 left font ',8' tc rgb '#777777'
set arrow from graph 0, first 1e-08 to graph 1, first 1e-08 nohead lc rgb '#999999' dt (4,4) front
set label '1e-8' at graph 1, first 1e-08 offset char 0.4,0 left font ',8' tc rgb '#777777'
set key at screen 0.7606, screen 0.9000 left top Left reverse box opaque samplen 4 spacing 1.1 font ',10'
set multiplot title "bar-twist-p2-nu0.45: 2523 tets, stable_neo_hookean E=1e+06 nu=0.45; 1 measured step, median of 3 repeats\nfastest to 1e-6: newton-clamp, 1.13x faster than the next, newton-project_on_demand" font ',12'

# panel 1: measured step 6
set lmargin at screen 0.0634
set rmargin at screen 0.7254
set tmargin at screen 0.9000
set bmargin at screen 0.0750
set ylabel 'relative energy error (g - g*) / |g0 - g*|'
set format y '1e%L'
set xlabel 'solve time of the step (s); median of the repeats; x0 at the left edge'
plot \
  'bar-twist-p2-nu0.45.dat' index 0 using ($1>0?$1:left):2 with linespoints lc rgb '#000000' dt 1 lw 3.0 pt 7 ps 0.8 pi 1 title 'newton-clamp (baseline) (fastest)', \
  'bar-twist-p2-nu0.45.dat' index 1 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 1 lw 1.6 pt 5 ps 0.8 pi 1 title 'newton-abs', \
  'bar-twist-p2-nu0.45.dat' index 2 using ($1>0?$1:left):2 with linespoints lc rgb '#114163' dt 1 lw 1.6 pt 9 ps 0.8 pi 1 title 'newton-project_on_demand', \
  'bar-twist-p2-nu0.45.dat' index 3 using ($1>0?$1:left):2 with linespoints lc rgb '#8fbbd9' dt 1 lw 1.6 pt 11 ps 0.8 pi 1 title 'newton-progressive', \
  'bar-twist-p2-nu0.45.dat' index 4 using ($1>0?$1:left):2 with linespoints lc rgb '#1f77b4' dt 1 lw 1.6 pt 13 ps 0.8 pi 1 title 'newton-trust_region_filter', \
  keyentry with lines lc rgb '#ffffff' title 'line style = line search:', \
  keyentry with lines lc rgb '#555555' lw 1.8 dt 1 title '  backtracking', \
  keyentry with lines lc rgb '#ffffff' title 'point = Hessian fix:', \
  keyentry with points lc rgb '#555555' pt 7 ps 1.0 title '  clamp', \
  keyentry with points lc rgb '#555555' pt 5 ps 1.0 title '  abs', \
  keyentry with points lc rgb '#555555' pt 9 ps 1.0 title '  project_on_demand', \
  keyentry with points lc rgb '#555555' pt 11 ps 1.0 title '  progressive', \
  keyentry with points lc rgb '#555555' pt 13 ps 1.0 title '  trust_region_filter'
unset multiplot
