if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1560,460 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1560,460 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'data_profile-all.png'
set multiplot layout 1,3 title "Data (More-Wild) profile, all (27 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set logscale x 10
set format x '1e%L'
set title 'relative energy error <= 1e-02'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'data_profile-all.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'data_profile-all.dat' index 4 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'data_profile-all.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'data_profile-all.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 8 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'data_profile-all.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-04'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 11 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'data_profile-all.dat' index 12 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 13 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 14 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'data_profile-all.dat' index 15 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'data_profile-all.dat' index 16 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'data_profile-all.dat' index 17 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 18 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 19 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 20 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'data_profile-all.dat' index 21 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-06'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 22 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'data_profile-all.dat' index 23 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 24 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 25 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'data_profile-all.dat' index 26 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'data_profile-all.dat' index 27 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'data_profile-all.dat' index 28 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 29 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 30 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 31 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'data_profile-all.dat' index 32 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
unset multiplot
set terminal svg size 1560,460 font 'DejaVu Sans,10' noenhanced
set output 'data_profile-all.svg'
set multiplot layout 1,3 title "Data (More-Wild) profile, all (27 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set logscale x 10
set format x '1e%L'
set title 'relative energy error <= 1e-02'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'data_profile-all.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'data_profile-all.dat' index 4 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'data_profile-all.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'data_profile-all.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 8 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'data_profile-all.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-04'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 11 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'data_profile-all.dat' index 12 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 13 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 14 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'data_profile-all.dat' index 15 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'data_profile-all.dat' index 16 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'data_profile-all.dat' index 17 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 18 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 19 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 20 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'data_profile-all.dat' index 21 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
set title 'relative energy error <= 1e-06'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 22 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton', \
  'data_profile-all.dat' index 23 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 24 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 25 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd', \
  'data_profile-all.dat' index 26 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (3,6) title 'vbd-accelerated', \
  'data_profile-all.dat' index 27 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (3,6) title 'admm_pd', \
  'data_profile-all.dat' index 28 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 29 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (3,6) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 30 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt (16,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 31 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (7,7) title 'aqp', \
  'data_profile-all.dat' index 32 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-pcg-gmg'
unset multiplot
