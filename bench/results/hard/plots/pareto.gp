set terminal png size 1500,950 font 'DejaVu Sans,11' noenhanced
set output 'pareto.png'
set rmargin at screen 0.70
# configurations by number (points are labelled with the number)
set label 1 " 1  newton-clamp-backtracking" at screen 0.72, screen 0.9200 left font ',10'
set label 2 " 2  newton-clamp-exact" at screen 0.72, screen 0.8933 left font ',10'
set label 3 " 3  newton-clamp-none" at screen 0.72, screen 0.8667 left font ',10'
set label 4 " 4  newton-abs-backtracking" at screen 0.72, screen 0.8400 left font ',10'
set label 5 " 5  newton-abs-exact" at screen 0.72, screen 0.8133 left font ',10'
set label 6 " 6  newton-abs-none" at screen 0.72, screen 0.7867 left font ',10'
set label 7 " 7  newton-shift-backtracking" at screen 0.72, screen 0.7600 left font ',10'
set label 8 " 8  newton-shift-exact" at screen 0.72, screen 0.7333 left font ',10'
set label 9 " 9  newton-shift-none" at screen 0.72, screen 0.7067 left font ',10'
set label 10 "10  newton-none-backtracking" at screen 0.72, screen 0.6800 left font ',10'
set label 11 "11  newton-none-exact" at screen 0.72, screen 0.6533 left font ',10'
set label 12 "12  newton-none-none" at screen 0.72, screen 0.6267 left font ',10'
set label 13 "13  lbfgs-backtracking" at screen 0.72, screen 0.6000 left font ',10'
set label 14 "14  lbfgs-exact" at screen 0.72, screen 0.5733 left font ',10'
set label 15 "15  lbfgs-none" at screen 0.72, screen 0.5467 left font ',10'
set label 16 "16  gradient_descent-backtracking" at screen 0.72, screen 0.5200 left font ',10'
set label 17 "17  gradient_descent-exact" at screen 0.72, screen 0.4933 left font ',10'
set label 18 "18  gradient_descent-none" at screen 0.72, screen 0.4667 left font ',10'
set label 19 "19  newton-project_on_demand-backtracking" at screen 0.72, screen 0.4400 left font ',10'
set label 20 "20  newton-progressive-backtracking" at screen 0.72, screen 0.4133 left font ',10'
set label 21 "21  newton-trust_region_filter-backtracking" at screen 0.72, screen 0.3867 left font ',10'
set label 22 "22  newton-clamp-nonmonotone" at screen 0.72, screen 0.3600 left font ',10'
set label 23 "23  newton_tr" at screen 0.72, screen 0.3333 left font ',10'
set label 24 "24  lbfgs-wolfe" at screen 0.72, screen 0.3067 left font ',10'
set label 25 "25  ncg-wolfe" at screen 0.72, screen 0.2800 left font ',10'
set label 26 "26  pd_local_global-anderson" at screen 0.72, screen 0.2533 left font ',10'
set label 27 "27  nlopt-lbfgs" at screen 0.72, screen 0.2267 left font ',10'
set label 28 "28  ipopt-clamp" at screen 0.72, screen 0.2000 left font ',10'
set label 29 "29  pd-backtracking" at screen 0.72, screen 0.1733 left font ',10'
set label 30 "30  pd-lbfgs5-backtracking" at screen 0.72, screen 0.1467 left font ',10'
set title "Speed against accuracy over 8 scene(s), each configuration with its own stopping rule\nlower left is better; the line joins the Pareto-optimal configurations"
set logscale xy
set grid lc rgb '#dddddd'
set format y '1e%L'
set xlabel "traj. time per step / baseline's (newton-clamp-backtracking): the report's 'traj. time' column, own stopping rule, geometric mean over scenes (not the headline's time to an accuracy)"
set ylabel "traj. dist / reference displacement: the 'traj. dist' column (geometric mean; clipped at 100)"
set key top left box opaque
set offsets graph 0.05, graph 0.1, graph 0.1, graph 0.05
plot 'pareto.dat' index 1 using 1:2 with lines lc rgb '#999999' lw 2 title 'Pareto front of the converged configurations', \
  'pareto.dat' index 0 using ($4==1?$2:1/0):3 with points pt 7 ps 1.6 lc rgb '#1f77b4' title 'converged on every step of every scene', \
  'pareto.dat' index 0 using ($4==0?$2:1/0):3 with points pt 9 ps 1.6 lc rgb '#d62728' title 'failed or stopped somewhere', \
  'pareto.dat' index 0 using 2:3:(sprintf('%d', $1)) with labels offset char 0.9,0.5 left font ',9' notitle
set terminal svg size 1500,950 font 'DejaVu Sans,11' noenhanced
set output 'pareto.svg'
replot
