if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1560,460 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1560,460 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'perf_profile-all.png'
set multiplot layout 1,3 title "Performance (Dolan-More) profile, all (12 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set title 'relative energy error <= 1e-02'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-all.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'perf_profile-all.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt 1 title 'lbfgs-pd5', \
  'perf_profile-all.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global', \
  'perf_profile-all.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global-aa5'
set title 'relative energy error <= 1e-03'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-all.dat' index 4 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'perf_profile-all.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt 1 title 'lbfgs-pd5', \
  'perf_profile-all.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global', \
  'perf_profile-all.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global-aa5'
set title 'relative energy error <= 1e-04'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-all.dat' index 8 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'perf_profile-all.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt 1 title 'lbfgs-pd5', \
  'perf_profile-all.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global', \
  'perf_profile-all.dat' index 11 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global-aa5'
unset multiplot
set terminal svg size 1560,460 font 'DejaVu Sans,10' noenhanced
set output 'perf_profile-all.svg'
set multiplot layout 1,3 title "Performance (Dolan-More) profile, all (12 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set title 'relative energy error <= 1e-02'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-all.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'perf_profile-all.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt 1 title 'lbfgs-pd5', \
  'perf_profile-all.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global', \
  'perf_profile-all.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global-aa5'
set title 'relative energy error <= 1e-03'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-all.dat' index 4 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'perf_profile-all.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt 1 title 'lbfgs-pd5', \
  'perf_profile-all.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global', \
  'perf_profile-all.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global-aa5'
set title 'relative energy error <= 1e-04'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-all.dat' index 8 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'perf_profile-all.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt 1 title 'lbfgs-pd5', \
  'perf_profile-all.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global', \
  'perf_profile-all.dat' index 11 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-local-global-aa5'
unset multiplot
