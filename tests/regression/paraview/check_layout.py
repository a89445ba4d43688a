"""pvpython script: open output written with output.region / output.stride / output.compression in
ParaView (XDMF through Xdmf3ReaderS, the VTK series through PVDReader) and check the extents, the
geometry and every value against the whole-grid output of the same run.
Usage: pvpython check_layout.py <variants.json>
Each variant: label, dir, prefix, ref (dir of the whole-grid output), cells (source grid), dx,
first (first selected cell), stride, out (expected output cells), arrays."""
import glob
import json
import sys

import numpy as np
from paraview import servermanager as sm
from paraview.simple import Delete, PVDReader, Xdmf3ReaderS
from vtkmodules.util.numpy_support import vtk_to_numpy

fail = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        fail.append(what)


def own_grid(data):
    """A deep copy of the grid block (the XDMF reader's arrays point into its own buffers, freed
    with the reader; a seaweed file also holds the particles as a second grid)."""
    if data.IsA("vtkMultiBlockDataSet"):
        blocks = [data.GetBlock(i) for i in range(data.GetNumberOfBlocks())]
        data = [b for b in blocks if b is not None and b.IsA("vtkImageData")][0]
    copy = data.NewInstance()
    copy.DeepCopy(data)
    return copy


def last_xdmf(d, prefix):
    files = sorted(glob.glob(f"{d}/{prefix}_[0-9]*.xmf"))
    reader = Xdmf3ReaderS(FileName=[files[-1]])
    reader.UpdatePipeline()
    data = own_grid(sm.Fetch(reader))
    Delete(reader)
    return files[-1].split("/")[-1], data


def last_pvd(d, prefix):
    reader = PVDReader(FileName=f"{d}/{prefix}.pvd")
    t = list(reader.TimestepValues)
    reader.UpdatePipeline(t[-1])
    data = own_grid(sm.Fetch(reader))
    Delete(reader)
    return data


def cell_array(data, name, n):
    """(nz, ny, nx, ncomp) array of a cell array of an image of n = (nx, ny, nz) cells."""
    a = vtk_to_numpy(data.GetCellData().GetArray(name))
    return a.reshape(n[2], n[1], n[0], -1)


def image_cells(data):
    ext = data.GetExtent()
    return [ext[1] - ext[0], ext[3] - ext[2], ext[5] - ext[4]]


def check_variant(v, label, data, ref):
    n, k, dx, first = v["out"], v["stride"], v["dx"], v["first"]
    check(data.GetNumberOfCells() == n[0] * n[1] * n[2],
          f"{label}: {data.GetNumberOfCells()} cells, expected {n[0]}x{n[1]}x{n[2]}")
    b = data.GetBounds()
    want = []
    for a in range(3):
        lo = (first[a] + 0.5 - 0.5 * k) * dx  # output cell centred on its source cell
        want += [lo, lo + n[a] * k * dx]
    check(all(abs(b[i] - want[i]) < 1e-9 for i in range(6)),
          f"{label}: bounds {tuple(round(x, 6) for x in b)} expected {tuple(round(x, 6) for x in want)}")
    if data.GetNumberOfCells() != n[0] * n[1] * n[2]:
        return
    # Geometry -> source cell: the centre of output cell m must be the centre of cell first + m k
    # of the whole-grid output; compare every array there, exactly.
    rn = v["cells"]
    idx = []
    for a in range(3):
        centres = b[2 * a] + (np.arange(n[a]) + 0.5) * k * dx
        src = np.rint(centres / dx - 0.5).astype(int)
        check(np.all(np.abs((src + 0.5) * dx - centres) < 1e-9 * max(1.0, dx * rn[a])) and
              src[0] == first[a] and src[-1] < rn[a],
              f"{label}: {'xyz'[a]} output centres on source cells {src[0]}..{src[-1]} step {k}")
        idx.append(src)
    for name in v["arrays"]:
        got = cell_array(data, name, n)
        whole = cell_array(ref, name, rn)
        want = whole[np.ix_(idx[2], idx[1], idx[0])]
        diff = int(np.count_nonzero(got != want))
        check(diff == 0 and got.size > 0,
              f"{label}: {name}: {got.size} values equal the whole-grid output at the source "
              f"cells ({diff} differ; range {got.min():.4g}..{got.max():.4g})")


for v in json.load(open(sys.argv[1])):
    name, ref = last_xdmf(v["ref"], v["prefix"])
    check(image_cells(ref) == v["cells"], f"{v['label']}: reference {name} has {image_cells(ref)} cells")
    xname, data = last_xdmf(v["dir"], v["prefix"])
    check(xname == name, f"{v['label']}: last XDMF {xname} is the reference's step")
    check_variant(v, f"{v['label']} XDMF", data, ref)
    check_variant(v, f"{v['label']} PVD/VTK", last_pvd(v["dir"], v["prefix"]), ref)
print(f"{len(fail)} failures")
sys.exit(1 if fail else 0)
