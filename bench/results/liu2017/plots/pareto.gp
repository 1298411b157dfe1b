set terminal png size 1500,950 font 'DejaVu Sans,11' noenhanced
set output 'pareto.png'
set rmargin at screen 0.70
# configurations by number (points are labelled with the number)
set label 1 " 1  newton-clamp-backtracking" at screen 0.72, screen 0.9200 left font ',10'
set label 2 " 2  newton-1it" at screen 0.72, screen 0.8800 left font ',10'
set label 3 " 3  newton-3it" at screen 0.72, screen 0.8400 left font ',10'
set label 4 " 4  lbfgs-pd5" at screen 0.72, screen 0.8000 left font ',10'
set label 5 " 5  lbfgs-pd5-10it" at screen 0.72, screen 0.7600 left font ',10'
set label 6 " 6  pd-local-global" at screen 0.72, screen 0.7200 left font ',10'
set label 7 " 7  pd-local-global-aa5" at screen 0.72, screen 0.6800 left font ',10'
set title "Speed against accuracy over 8 scene(s), each configuration with its own stopping rule\nlower left is better; the line joins the Pareto-optimal configurations"
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
