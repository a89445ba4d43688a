"""pvpython script: open a tank output directory and check arrays, extents and values.
Usage: pvpython check_output.py <dir> <nx> <ny> <nz>"""
import glob
import sys

from paraview import servermanager as sm
from paraview.simple import PVDReader, Xdmf3ReaderS

out, nx, ny, nz = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
fail = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        fail.append(what)


def check_dataset(label, data):
    cd = data.GetCellData()
    names = sorted(cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays()))
    check(names == ["density", "pressure", "velocity"], f"{label}: arrays {names}")
    check(data.GetNumberOfCells() == nx * ny * nz, f"{label}: {data.GetNumberOfCells()} cells")
    b = data.GetBounds()
    check(abs(b[1] - nx * 0.01) < 1e-6 and abs(b[3] - ny * 0.01) < 1e-6 and
          abs(b[5] - nz * 0.01) < 1e-6, f"{label}: bounds {b}")
    lo, hi = cd.GetArray("density").GetRange()
    check(950 < lo <= hi < 1050, f"{label}: density range [{lo:.3f}, {hi:.3f}] kg/m^3 within 5% of 998")
    vmax = cd.GetArray("velocity").GetRange(-1)[1]
    check(0.1 < vmax < 0.5, f"{label}: |velocity| max {vmax:.4f} m/s (jet of 0.3 m/s on)")


xmf = sorted(glob.glob(out + "/tank_*.xmf"))
check(len(xmf) == 3, f"{len(xmf)} XDMF files")
reader = Xdmf3ReaderS(FileName=[xmf[-1]])
reader.UpdatePipeline()
check_dataset("XDMF " + xmf[-1].split("/")[-1], sm.Fetch(reader))

pvd = PVDReader(FileName=out + "/tank.pvd")
times = list(pvd.TimestepValues)
check(len(times) == 3, f"PVD time steps {times}")
pvd.UpdatePipeline(times[-1])
check_dataset("PVD last step", sm.Fetch(pvd))
sys.exit(1 if fail else 0)
