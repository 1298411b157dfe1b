"""Open a distributed run's partitioned output in ParaView (pvbatch) and compare it with
the serial run's (tests/test_petsc_paraview.sh).

usage: pvbatch petsc_paraview.py DIR_SERIAL DIR_MPI
Reads each folder's .pvd series (the MPI one lists .pvtu frames of one .vtu piece per
rank) at its last time, merges the pieces' shared points (CleantoGrid), and checks: the
same number of time steps, cells and merged points, and the same range of every
displacement component to 1e-8 of the largest. Exits 1 otherwise."""
import glob
import sys

from paraview.simple import CleantoGrid, OpenDataFile, servermanager


def load(run):
    pvd = glob.glob(run + "/*.pvd")[0]
    r = OpenDataFile(pvd)
    t = r.TimestepValues
    last = t[-1] if t else 0
    c = CleantoGrid(Input=r)
    c.UpdatePipeline(time=last)
    d = servermanager.Fetch(c)
    a = d.GetPointData().GetArray("displacement")
    rng = [a.GetRange(k) for k in range(3)]
    return len(t), d.GetNumberOfCells(), d.GetNumberOfPoints(), rng


def main():
    s, p = load(sys.argv[1]), load(sys.argv[2])
    pieces = len(glob.glob(sys.argv[2] + "/*_r*.vtu"))
    print(f"serial: {s[0]} frames, {s[1]} cells, {s[2]} points; mpi ({pieces} pieces): {p[0]} frames, {p[1]} cells, "
          f"{p[2]} points after merging")
    scale = max(max(abs(x) for x in r) for r in s[3]) or 1
    err = max(abs(a - b) for ra, rb in zip(s[3], p[3]) for a, b in zip(ra, rb)) / scale
    print(f"displacement ranges agree to {err:.2e} of the largest")
    ok = s[:3] == p[:3] and err <= 1e-8 and pieces > 0
    print("paraview: OK" if ok else "paraview: FAIL")
    sys.exit(0 if ok else 1)


main()
