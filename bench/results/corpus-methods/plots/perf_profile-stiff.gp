if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1560,460 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1560,460 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'perf_profile-stiff.png'
set multiplot layout 1,3 title "Performance (Dolan-More) profile, stiff (16 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set title 'relative energy error <= 1e-02'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-stiff.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'perf_profile-stiff.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'perf_profile-stiff.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'perf_profile-stiff.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'perf_profile-stiff.dat' index 4 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'perf_profile-stiff.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'perf_profile-stiff.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'perf_profile-stiff.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'perf_profile-stiff.dat' index 8 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'perf_profile-stiff.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'perf_profile-stiff.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-04'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-stiff.dat' index 11 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'perf_profile-stiff.dat' index 12 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'perf_profile-stiff.dat' index 13 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'perf_profile-stiff.dat' index 14 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'perf_profile-stiff.dat' index 15 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'perf_profile-stiff.dat' index 16 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'perf_profile-stiff.dat' index 17 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'perf_profile-stiff.dat' index 18 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'perf_profile-stiff.dat' index 19 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'perf_profile-stiff.dat' index 20 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'perf_profile-stiff.dat' index 21 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-06'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-stiff.dat' index 22 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'perf_profile-stiff.dat' index 23 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'perf_profile-stiff.dat' index 24 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'perf_profile-stiff.dat' index 25 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'perf_profile-stiff.dat' index 26 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'perf_profile-stiff.dat' index 27 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'perf_profile-stiff.dat' index 28 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'perf_profile-stiff.dat' index 29 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'perf_profile-stiff.dat' index 30 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'perf_profile-stiff.dat' index 31 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'perf_profile-stiff.dat' index 32 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
unset multiplot
set terminal svg size 1560,460 font 'DejaVu Sans,10' noenhanced
set output 'perf_profile-stiff.svg'
set multiplot layout 1,3 title "Performance (Dolan-More) profile, stiff (16 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set title 'relative energy error <= 1e-02'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-stiff.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'perf_profile-stiff.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'perf_profile-stiff.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'perf_profile-stiff.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'perf_profile-stiff.dat' index 4 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'perf_profile-stiff.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'perf_profile-stiff.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'perf_profile-stiff.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'perf_profile-stiff.dat' index 8 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'perf_profile-stiff.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'perf_profile-stiff.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-04'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-stiff.dat' index 11 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'perf_profile-stiff.dat' index 12 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'perf_profile-stiff.dat' index 13 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'perf_profile-stiff.dat' index 14 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'perf_profile-stiff.dat' index 15 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'perf_profile-stiff.dat' index 16 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'perf_profile-stiff.dat' index 17 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'perf_profile-stiff.dat' index 18 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'perf_profile-stiff.dat' index 19 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'perf_profile-stiff.dat' index 20 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'perf_profile-stiff.dat' index 21 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-06'
set xlabel 'tau (time / best time on the instance)'
set ylabel 'fraction of instances'
plot 'perf_profile-stiff.dat' index 22 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'perf_profile-stiff.dat' index 23 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'perf_profile-stiff.dat' index 24 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'perf_profile-stiff.dat' index 25 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'perf_profile-stiff.dat' index 26 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'perf_profile-stiff.dat' index 27 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'perf_profile-stiff.dat' index 28 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'perf_profile-stiff.dat' index 29 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'perf_profile-stiff.dat' index 30 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'perf_profile-stiff.dat' index 31 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'perf_profile-stiff.dat' index 32 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
unset multiplot
