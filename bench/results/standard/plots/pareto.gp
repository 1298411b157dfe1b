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
set label 2 " 2  newton-shift-backtracking" at screen 0.72, screen 0.8880 left font ',10' tc rgb '#1f77b4'
set label 3 " 3  newton-none-backtracking" at screen 0.72, screen 0.8560 left font ',10' tc rgb '#1f77b4'
set label 4 " 4  newton-project_on_demand-backtracking" at screen 0.72, screen 0.8240 left font ',10' tc rgb '#1f77b4'
set label 5 " 5  newton-progressive-backtracking" at screen 0.72, screen 0.7920 left font ',10' tc rgb '#1f77b4'
set label 6 " 6  newton-trust_region_filter-backtracking" at screen 0.72, screen 0.7600 left font ',10' tc rgb '#1f77b4'
set label 7 " 7  newton-clamp-none" at screen 0.72, screen 0.7280 left font ',10' tc rgb '#1f77b4'
set label 8 " 8  newton-clamp-nonmonotone" at screen 0.72, screen 0.6960 left font ',10' tc rgb '#1f77b4'
set label 9 " 9  newton_tr" at screen 0.72, screen 0.6640 left font ',10' tc rgb '#d62728'
set label 10 "10  newton-clamp-pcg-gmg-ew2" at screen 0.72, screen 0.6320 left font ',10' tc rgb '#1f77b4'
set label 11 "11  lbfgs-wolfe" at screen 0.72, screen 0.6000 left font ',10' tc rgb '#2ca02c'
set label 12 "12  bcqn" at screen 0.72, screen 0.5680 left font ',10' tc rgb '#ff7f0e'
set label 13 "13  lbfgs-wolfe-lumped" at screen 0.72, screen 0.5360 left font ',10' tc rgb '#2ca02c'
set label 14 "14  ncg" at screen 0.72, screen 0.5040 left font ',10' tc rgb '#9467bd'
set label 15 "15  pd-lbfgs5-backtracking" at screen 0.72, screen 0.4720 left font ',10' tc rgb '#8c564b'
set label 16 "16  pd_local_global" at screen 0.72, screen 0.4400 left font ',10' tc rgb '#e377c2'
set label 17 "17  pd_local_global-anderson" at screen 0.72, screen 0.4080 left font ',10' tc rgb '#e377c2'
set label 18 "18  admm_pd" at screen 0.72, screen 0.3760 left font ',10' tc rgb '#17becf'
set label 19 "19  mixed_fem" at screen 0.72, screen 0.3440 left font ',10' tc rgb '#bcbd22'
set label 20 "20  aqp" at screen 0.72, screen 0.3120 left font ',10' tc rgb '#7f7f7f'
set label 21 "21  pd_local_global-chebyshev" at screen 0.72, screen 0.2800 left font ',10' tc rgb '#e377c2'
set label 22 "22  vbd-accelerated" at screen 0.72, screen 0.2480 left font ',10' tc rgb '#1f77b4'
set label 23 "23  jacobi_chebyshev" at screen 0.72, screen 0.2160 left font ',10' tc rgb '#d62728'
set label 24 "24  nlopt-lbfgs" at screen 0.72, screen 0.1840 left font ',10' tc rgb '#2ca02c'
set label 25 "25  ipopt-clamp" at screen 0.72, screen 0.1520 left font ',10' tc rgb '#ff7f0e'
set title "Own stopping rule over 19 scene(s) (the report's 'Own stopping rule' table): lower left is better\nfastest converged everywhere: newton-project_on_demand-backtracking (0.66x the baseline's time); closest: ipopt-clamp (1.8e-09)"
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
