if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1500,950 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1500,950 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'pareto.png'
set rmargin at screen 0.70
set lmargin at screen 0.08
set bmargin at screen 0.17
# configurations by number (points are labelled with the number), coloured by optimizer family
set label 1 " 1  newton-clamp-backtracking (baseline)" at screen 0.72, screen 0.9200 left font ',10' tc rgb '#000000'
set label 2 " 2  lbfgs-pd5" at screen 0.72, screen 0.8800 left font ',10' tc rgb '#d62728'
set label 3 " 3  pd-local-global" at screen 0.72, screen 0.8400 left font ',10' tc rgb '#2ca02c'
set label 4 " 4  pd-local-global-aa5" at screen 0.72, screen 0.8000 left font ',10' tc rgb '#2ca02c'
set title "Own stopping rule over 8 scene(s) (the report's 'Own stopping rule' table): lower left is better\nfastest converged everywhere: pd-local-global-aa5 (0.75x the baseline's time); closest: newton-clamp-backtracking (1.5e-08)"
set logscale xy
set grid lc rgb '#dddddd'
set format y '1e%L'
set xlabel "traj. time / baseline (solve time per step over newton-clamp-backtracking's; geometric mean over the scenes)"
set ylabel "traj. dist / ref. motion (m/m; geometric mean over the scenes, clipped at 100)"
set key at screen 0.08, screen 0.085 left top Left reverse box spacing 1.2
set offsets graph 0.05, graph 0.1, graph 0.1, graph 0.05
plot 'pareto.dat' index 1 using 1:2 with lines lc rgb '#999999' lw 2 title 'Pareto front of the configurations that converged everywhere', \
  'pareto.dat' index 0 using ($4==1?$2:1/0):3:6 with points pt 7 ps 1.8 lc rgb variable notitle, \
  'pareto.dat' index 0 using ($4==0?$2:1/0):3:6 with points pt 8 ps 1.8 lw 2 lc rgb variable notitle, \
  'pareto.dat' index 2 using 1:2:3 with labels offset char 1.0,0.6 left font ',9' notitle, \
  keyentry with points pt 7 ps 1.8 lc rgb '#555555' title 'converged on every step of every scene (colour: optimizer family, as in the scene plots)', \
  keyentry with points pt 8 ps 1.8 lw 2 lc rgb '#555555' title 'failed or stopped somewhere'
set terminal svg size 1500,950 font 'DejaVu Sans,10' noenhanced
set output 'pareto.svg'
replot
