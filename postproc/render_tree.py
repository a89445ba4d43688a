"""Render trees swaying in the wind (PNG) with ParaView, headless:

    postproc/headless.sh pvpython postproc/render_tree.py <output.dir> <out.png> [index]

Reads <output.dir>/tree_nodes.pvd (nodes and links; branches drawn as tubes whose radius is the
link radius, coloured by displacement) and <output.dir>/wind.pvd (the MAC wind: a vertical slice
along the wind through the first tree coloured by speed, and streamlines seeded on a vertical
line upstream of the trees). `index` picks the time step (default: the last).
"""
import os

from pv_common import open_series_at, render_arguments, save_png, white_view
from paraview.simple import (CellDatatoPointData, ColorBy, OpenDataFile,
                             Render, Show, Slice, StreamTracer, Tube,
                             UpdatePipeline)

out_dir, png, index = render_arguments("tree_nodes.pvd", "tree")
view = white_view()
trees, t = open_series_at(view, out_dir, "tree_nodes.pvd", index)
(x0, x1, y0, y1, z0, z1) = trees.GetDataInformation().GetBounds()
centre = [0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)]

wind_pvd = os.path.join(out_dir, "wind.pvd")
if os.path.exists(wind_pvd):
    wind = OpenDataFile(wind_pvd)
    UpdatePipeline(time=t, proxy=wind)
    (wx0, wx1, wy0, wy1, wz0, wz1) = wind.GetDataInformation().GetBounds()
    sl = Slice(Input=wind)
    sl.SliceType.Normal = [0, 1, 0]
    # Just behind the trees, but inside the wind's box: a forest fills the box's whole width,
    # and a slice on its face is empty (nothing drawn).
    behind = min(centre[1] + 0.5 * (y1 - y0) + 0.5, wy1 - 0.02 * (wy1 - wy0))
    sl.SliceType.Origin = [centre[0], behind, centre[2]]
    d = Show(sl, view)
    ColorBy(d, ("CELLS", "velocity", "Magnitude"))
    d.Opacity = 0.7
    pts = CellDatatoPointData(Input=wind)
    st = StreamTracer(Input=pts, SeedType="Line")
    st.Vectors = ["POINTS", "velocity"]
    st.SeedType.Point1 = [wx0 + 0.05 * (wx1 - wx0), centre[1], wz0 + 0.05 * (wz1 - wz0)]
    st.SeedType.Point2 = [wx0 + 0.05 * (wx1 - wx0), centre[1], wz0 + 0.9 * (wz1 - wz0)]
    st.SeedType.Resolution = 40
    st.MaximumStreamlineLength = wx1 - wx0
    sd = Show(st, view)
    sd.ColorArrayName = ["POINTS", ""]
    sd.DiffuseColor = [0.2, 0.2, 0.2]
    sd.AmbientColor = [0.2, 0.2, 0.2]

tube = Tube(Input=trees)
tube.Scalars = ["POINTS", "radius"]
tube.VaryRadius = "By Absolute Scalar"
tube.NumberofSides = 12
td = Show(tube, view)
ColorBy(td, ("POINTS", "displacement"))
td.RescaleTransferFunctionToDataRange(True)
view.ResetCamera()
h = max(z1 - z0, x1 - x0, 1.0)
view.CameraFocalPoint = centre
view.CameraPosition = [centre[0] - 0.6 * h, centre[1] - 2.2 * h, centre[2] + 0.5 * h]
view.CameraViewUp = [0, 0, 1]
Render(view)
save_png(view, png)
print("wrote", png, "time", t)
