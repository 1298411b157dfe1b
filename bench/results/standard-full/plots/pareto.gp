set terminal png size 1500,950 font 'DejaVu Sans,11' noenhanced
set output 'pareto.png'
set rmargin at screen 0.70
# configurations by number (points are labelled with the number)
set label 1 " 1  newton-clamp-backtracking" at screen 0.72, screen 0.9200 left font ',10'
set label 2 " 2  newton-clamp-exact" at screen 0.72, screen 0.8836 left font ',10'
set label 3 " 3  newton-clamp-none" at screen 0.72, screen 0.8473 left font ',10'
set label 4 " 4  newton-abs-backtracking" at screen 0.72, screen 0.8109 left font ',10'
set label 5 " 5  newton-abs-exact" at screen 0.72, screen 0.7745 left font ',10'
set label 6 " 6  newton-abs-none" at screen 0.72, screen 0.7382 left font ',10'
set label 7 " 7  newton-shift-backtracking" at screen 0.72, screen 0.7018 left font ',10'
set label 8 " 8  newton-shift-exact" at screen 0.72, screen 0.6655 left font ',10'
set label 9 " 9  newton-shift-none" at screen 0.72, screen 0.6291 left font ',10'
set label 10 "10  newton-none-backtracking" at screen 0.72, screen 0.5927 left font ',10'
set label 11 "11  newton-none-exact" at screen 0.72, screen 0.5564 left font ',10'
set label 12 "12  newton-none-none" at screen 0.72, screen 0.5200 left font ',10'
set label 13 "13  lbfgs-backtracking" at screen 0.72, screen 0.4836 left font ',10'
set label 14 "14  lbfgs-exact" at screen 0.72, screen 0.4473 left font ',10'
set label 15 "15  lbfgs-none" at screen 0.72, screen 0.4109 left font ',10'
set label 16 "16  gradient_descent-backtracking" at screen 0.72, screen 0.3745 left font ',10'
set label 17 "17  gradient_descent-exact" at screen 0.72, screen 0.3382 left font ',10'
set label 18 "18  gradient_descent-none" at screen 0.72, screen 0.3018 left font ',10'
set label 19 "19  nlopt-lbfgs" at screen 0.72, screen 0.2655 left font ',10'
set label 20 "20  ipopt-clamp" at screen 0.72, screen 0.2291 left font ',10'
set label 21 "21  pd-backtracking" at screen 0.72, screen 0.1927 left font ',10'
set label 22 "22  pd-lbfgs5-backtracking" at screen 0.72, screen 0.1564 left font ',10'
set title "Speed against accuracy over 24 scene(s), each configuration with its own stopping rule\nlower left is better; the line joins the Pareto-optimal configurations"
set logscale xy
set grid lc rgb '#dddddd'
set format y '1e%L'
set xlabel 'trajectory solve time per step / baseline (newton-clamp-backtracking), geometric mean over scenes'
set ylabel 'max distance to reference trajectory / reference displacement (geometric mean; clipped at 100)'
set key top left box opaque
set offsets graph 0.05, graph 0.1, graph 0.1, graph 0.05
plot 'pareto.dat' index 1 using 1:2 with lines lc rgb '#999999' lw 2 title 'Pareto front of the converged configurations', \
  'pareto.dat' index 0 using ($4==1?$2:1/0):3 with points pt 7 ps 1.6 lc rgb '#1f77b4' title 'converged on every step of every scene', \
  'pareto.dat' index 0 using ($4==0?$2:1/0):3 with points pt 9 ps 1.6 lc rgb '#d62728' title 'failed or stopped somewhere', \
  'pareto.dat' index 0 using 2:3:(sprintf('%d', $1)) with labels offset char 0.9,0.5 left font ',9' notitle
