# The PETSc / MPI shell tests' first lines (sourced; $1 = elastopt, $2 = the backend module):
# ELASTOPT, MODULE and here set; skip (77) without the module, without mpirun, or when the
# CLI does not load the backend.
set -u
ELASTOPT=$1
MODULE=$2
here=$(cd "$(dirname "$0")" && pwd)
[ -f "$MODULE" ] || { echo "skip: PETSc backend not built ($MODULE)"; exit 77; }
command -v mpirun >/dev/null || { echo "skip: no mpirun"; exit 77; }
"$ELASTOPT" list | grep -q "^  petsc_ksp " || { echo "skip: the CLI does not load the backend (sanitizer build?)"; exit 77; }
