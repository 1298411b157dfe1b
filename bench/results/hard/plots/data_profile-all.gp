if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
    set terminal pngcairo size 1560,880 font 'DejaVu Sans,10' noenhanced
} else {
    set terminal png size 1560,880 font 'DejaVu Sans,11' noenhanced  # draws every dash type solid
}
set output 'data_profile-all.png'
set multiplot layout 2,3 title "Data (More-Wild) profile, all (17 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set logscale x 10
set format x '1e%L'
set title 'relative energy error <= 1e-02'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 4 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 8 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 11 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 12 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 13 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 14 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 15 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 16 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 17 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 18 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 19 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 20 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 21 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 22 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 23 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 24 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 25 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 26 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-03'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 27 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 28 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 29 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 30 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 31 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 32 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 33 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 34 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 35 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 36 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 37 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 38 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 39 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 40 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 41 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 42 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 43 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 44 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 45 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 46 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 47 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 48 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 49 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 50 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 51 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 52 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 53 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-04'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 54 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 55 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 56 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 57 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 58 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 59 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 60 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 61 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 62 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 63 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 64 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 65 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 66 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 67 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 68 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 69 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 70 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 71 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 72 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 73 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 74 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 75 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 76 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 77 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 78 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 79 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 80 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-06'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 81 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 82 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 83 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 84 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 85 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 86 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 87 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 88 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 89 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 90 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 91 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 92 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 93 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 94 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 95 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 96 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 97 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 98 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 99 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 100 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 101 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 102 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 103 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 104 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 105 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 106 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 107 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-08'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 108 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 109 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 110 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 111 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 112 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 113 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 114 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 115 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 116 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 117 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 118 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 119 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 120 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 121 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 122 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 123 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 124 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 125 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 126 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 127 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 128 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 129 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 130 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 131 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 132 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 133 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 134 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
unset multiplot
set terminal svg size 1560,880 font 'DejaVu Sans,10' noenhanced
set output 'data_profile-all.svg'
set multiplot layout 2,3 title "Data (More-Wild) profile, all (17 instances = measured steps; CPU time)"
set logscale x 2
set yrange [0:1.02]
set grid lc rgb '#dddddd'
set key bottom right font ',8'
set logscale x 10
set format x '1e%L'
set title 'relative energy error <= 1e-02'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 0 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 1 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 2 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 3 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 4 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 5 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 6 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 7 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 8 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 9 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 10 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 11 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 12 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 13 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 14 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 15 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 16 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 17 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 18 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 19 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 20 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 21 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 22 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 23 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 24 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 25 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 26 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-03'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 27 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 28 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 29 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 30 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 31 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 32 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 33 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 34 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 35 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 36 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 37 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 38 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 39 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 40 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 41 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 42 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 43 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 44 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 45 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 46 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 47 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 48 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 49 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 50 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 51 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 52 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 53 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-04'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 54 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 55 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 56 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 57 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 58 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 59 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 60 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 61 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 62 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 63 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 64 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 65 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 66 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 67 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 68 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 69 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 70 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 71 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 72 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 73 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 74 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 75 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 76 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 77 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 78 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 79 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 80 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-06'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 81 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 82 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 83 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 84 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 85 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 86 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 87 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 88 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 89 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 90 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 91 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 92 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 93 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 94 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 95 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 96 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 97 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 98 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 99 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 100 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 101 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 102 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 103 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 104 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 105 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 106 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 107 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
set title 'relative energy error <= 1e-08'
set xlabel 'budget (gradient-equivalents of time)'
set ylabel 'fraction of instances'
plot 'data_profile-all.dat' index 108 using 1:2 with steps lw 2.5 lc rgb '#000000' dt 1 title 'newton-clamp-backtracking', \
  'data_profile-all.dat' index 109 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-clamp-none', \
  'data_profile-all.dat' index 110 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-abs-backtracking', \
  'data_profile-all.dat' index 111 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-abs-none', \
  'data_profile-all.dat' index 112 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-shift-backtracking', \
  'data_profile-all.dat' index 113 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-shift-none', \
  'data_profile-all.dat' index 114 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-none-backtracking', \
  'data_profile-all.dat' index 115 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'newton-none-none', \
  'data_profile-all.dat' index 116 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-project_on_demand-backtracking', \
  'data_profile-all.dat' index 117 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-progressive-backtracking', \
  'data_profile-all.dat' index 118 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-trust_region_filter-backtracking', \
  'data_profile-all.dat' index 119 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (3,6) title 'newton-clamp-nonmonotone', \
  'data_profile-all.dat' index 120 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'newton_tr', \
  'data_profile-all.dat' index 121 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt 1 title 'newton-clamp-pcg-gmg-ew2', \
  'data_profile-all.dat' index 122 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt (16,6,3,6) title 'ipopt-clamp', \
  'data_profile-all.dat' index 123 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (7,7) title 'lbfgs-wolfe', \
  'data_profile-all.dat' index 124 using 1:2 with steps lw 1.5 lc rgb '#9467bd' dt (16,6,3,6,3,6) title 'bcqn', \
  'data_profile-all.dat' index 125 using 1:2 with steps lw 1.5 lc rgb '#8c564b' dt (7,7) title 'ncg-wolfe', \
  'data_profile-all.dat' index 126 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-anderson', \
  'data_profile-all.dat' index 127 using 1:2 with steps lw 1.5 lc rgb '#17becf' dt (16,8) title 'admm_pd', \
  'data_profile-all.dat' index 128 using 1:2 with steps lw 1.5 lc rgb '#bcbd22' dt 1 title 'mixed_fem', \
  'data_profile-all.dat' index 129 using 1:2 with steps lw 1.5 lc rgb '#7f7f7f' dt (16,6,3,6) title 'aqp', \
  'data_profile-all.dat' index 130 using 1:2 with steps lw 1.5 lc rgb '#e377c2' dt 1 title 'pd_local_global-chebyshev', \
  'data_profile-all.dat' index 131 using 1:2 with steps lw 1.5 lc rgb '#1f77b4' dt (16,8) title 'vbd-accelerated', \
  'data_profile-all.dat' index 132 using 1:2 with steps lw 1.5 lc rgb '#d62728' dt (16,8) title 'jacobi_chebyshev', \
  'data_profile-all.dat' index 133 using 1:2 with steps lw 1.5 lc rgb '#2ca02c' dt 1 title 'pd-lbfgs5-backtracking', \
  'data_profile-all.dat' index 134 using 1:2 with steps lw 1.5 lc rgb '#ff7f0e' dt (16,6,3,6) title 'nlopt-lbfgs'
unset multiplot
