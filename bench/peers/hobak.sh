#!/bin/bash
# The static cantilever in HOBAK (github.com/theodorekim/HOBAKv1), on elastopt's mesh.
# HOBAK's licence does not allow copying it into this repository: this script clones it (or
# uses HOBAK_SRC), writes a small driver main into the work folder and builds everything
# there, outside the repository. Nothing of HOBAK is committed.
#
#   bench/peers/hobak.sh MESH.node [WORK=/tmp/hobak-peers] [RTOL=1e-9] [CGTOL=1e-10]
#
# The driver: HOBAK's TET_MESH + NEO_HOOKEAN_BW (mu/2 (I_C-3) - mu log J + lambda/2 log^2 J,
# the same energy as elastopt's neo_hookean) + the QUASISTATIC timestepper (Newton on the
# clamped Hessian, full steps, Eigen ConjugateGradient with its diagonal preconditioner),
# clamp = a kinematic CUBE holding the vertices with x <= 0, gravity through addGravity
# (HOBAK's lumped one-ring volume load V/4 per vertex = the consistent load; density 1000
# carried by the body force). One Newton iteration per solve() call (the private iteration
# caps are reset from a subclass), stopped when |R_k| <= RTOL |R_0| with R the filtered force;
# CG relative tolerance CGTOL (Eigen's default, machine epsilon, would not stop). CPU time:
# CLOCK_PROCESS_CPUTIME_ID around the Newton loop, OMP_NUM_THREADS=1.
# Writes WORK/result.txt (rest x y z, displacement) and prints "RESULT iterations ..."; compare
# with a FEniCSx .npz of bench/peers/fenicsx_cantilever.py --save by bench/peers/hobak_compare.py.
set -euo pipefail
mesh=${1:?usage: hobak.sh MESH.node [WORK]}
mesh=$(cd "$(dirname "$mesh")" && pwd)/$(basename "${mesh%.node}")
work=${2:-/tmp/hobak-peers}
rtol=${3:-1e-9}
cgtol=${4:-1e-10}
case "$work" in "$(cd "$(dirname "$0")/../.." && pwd)"*) echo "hobak.sh: WORK must be outside the repository" >&2; exit 2;; esac
mkdir -p "$work"
src=${HOBAK_SRC:-$work/HOBAKv1}
if [ ! -d "$src/src/Timestepper" ]; then
  git clone -q --depth 1 https://github.com/theodorekim/HOBAKv1 "$src" || { echo "hobak.sh: cannot get HOBAK (set HOBAK_SRC to a checkout)"; exit 0; }
fi
cat > "$work/main.cpp" <<'EOF'
// static cantilever driven through HOBAK's QUASISTATIC timestepper (Newton on the clamped
// Hessian, Eigen CG, Baraff-Witkin constraints); one Newton iteration per solve() call
#include <cstdio>
#include <cmath>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include "Geometry/TET_MESH.h"
#include "Geometry/CUBE.h"
#include "Hyperelastic/Volume/NEO_HOOKEAN_BW.h"
#define private protected   // the iteration caps of QUASISTATIC are private; same layout
#include "Timestepper/QUASISTATIC.h"
#undef private
using namespace HOBAK;
struct QS : public TIMESTEPPER::QUASISTATIC {
  QS(TET_MESH& m, VOLUME::HYPERELASTIC& h) : QUASISTATIC(m, h) {}
  void cfg(REAL cgtol) { _minIterations = 1; _maxIterations = 1; _residualTolerance = 0; _cgSolver.setTolerance(cgtol); }
  REAL res() const { return _residual; }
  REAL step() const { return _solution.norm(); }
  REAL disp() const { return _tetMesh.getDisplacement().norm(); }
  int cgits() const { return (int)_cgSolver.iterations(); }
};
static std::vector<std::vector<std::string>> rows(const std::string& fn) {
  std::ifstream f(fn); std::string l; std::vector<std::vector<std::string>> out;
  while (std::getline(f, l)) { auto p = l.find('#'); if (p != std::string::npos) l = l.substr(0, p);
    std::istringstream s(l); std::vector<std::string> r; std::string w; while (s >> w) r.push_back(w); if (!r.empty()) out.push_back(r); }
  return out;
}
static double cpu() { timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
int main(int argc, char** argv) {
  if (argc < 4) { fprintf(stderr, "usage: main BASE(.node/.ele) OUT.txt rtol [cgtol] [maxit]\n"); return 2; }
  std::string base = argv[1]; double rtol = atof(argv[3]); double cgtol = argc > 4 ? atof(argv[4]) : 1e-10; int maxit = argc > 5 ? atoi(argv[5]) : 100;
  auto nr = rows(base + ".node"), er = rows(base + ".ele");
  int n = std::stoi(nr[0][0]), m = std::stoi(er[0][0]), first = std::stoi(nr[1][0]);
  std::vector<VECTOR3> V(n); std::vector<VECTOR4I> T(m);
  for (int i = 0; i < n; i++) V[i] = VECTOR3(std::stod(nr[1 + i][1]), std::stod(nr[1 + i][2]), std::stod(nr[1 + i][3]));
  for (int i = 0; i < m; i++) for (int k = 0; k < 4; k++) T[i][k] = std::stoi(er[1 + i][1 + k]) - first;
  const double E = 1e7, nu = 0.3, rho = 1000, g = -9.81;
  const double mu = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  double c0 = cpu();
  TET_MESH mesh(V, T);
  VOLUME::NEO_HOOKEAN_BW mat(mu, lam);
  QS qs(mesh, mat);
  CUBE clamp(VECTOR3(-0.5 + 1e-9, 0.05, 0.05), 1.0);   // x in [-1, 1e-9]
  qs.attachKinematicConstraints(&clamp);
  qs.addGravity(VECTOR3(0, 0, rho * g));   // HOBAK's mass is the one-ring volume: density 1, so the body force carries rho
  qs.cfg(cgtol);
  double setup = cpu() - c0;
  double t0 = cpu(), r0 = -1; int it = 0, cgsum = 0;
  for (; it < maxit; it++) {
    qs.solve(false);
    double r = std::sqrt(qs.res());   // |b| at the start of this iteration (filtered force)
    cgsum += qs.cgits();
    if (r0 < 0) r0 = r;
    printf("iter %d |R| %.3e |dx| %.3e cg %d cpu %.3f\n", it, r, qs.step(), qs.cgits(), cpu() - t0); fflush(stdout);
    // |R| <= rtol |R_0|, or the step |dx| <= 1e-8 |u| (PETSc's stol: the residual's round-off floor)
    if ((it > 0 && r <= rtol * r0) || qs.step() <= 1e-8 * qs.disp()) { it++; break; }
  }
  double solve = cpu() - t0;
  printf("RESULT iterations %d cg_total %d cpu %.6f setup %.6f\n", it, cgsum, solve, setup);
  FILE* f = fopen(argv[2], "w");
  const auto& X = mesh.restVertices(); const auto& x = mesh.vertices();
  for (int i = 0; i < n; i++) fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g\n", X[i][0], X[i][1], X[i][2], x[i][0] - X[i][0], x[i][1] - X[i][1], x[i][2] - X[i][2]);
  fclose(f);
  return 0;
}
EOF
cd "$src"
mkdir -p "$work/obj"
INC="-I. -Isrc -Isrc/util -Iext/eigen-3.3.7 -Iext/spectra-0.8.1/include -Iext/rapidjson"
# the solver sources; the OpenGL viewer and the scene file reader are left out
for f in $(find src -name '*.cpp' | grep -v -E 'DRAW_GL|FIELD_3D|FILE_IO' | sort) "$work/main.cpp"; do
  o="$work/obj/$(echo "$f" | tr / _).o"
  [ -f "$o" ] || g++ -c -O3 -DNDEBUG -std=c++14 -fopenmp -w $INC "$f" -o "$o"
done
g++ -fopenmp "$work"/obj/*.o -o "$work/hobak_cantilever"
OMP_NUM_THREADS=1 "$work/hobak_cantilever" "$mesh" "$work/result.txt" "$rtol" "$cgtol" 200
