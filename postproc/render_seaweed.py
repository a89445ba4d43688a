"""Render a snapshot of the seaweed plants and the flow (PNG) with ParaView, headless:

    postproc/headless.sh pvpython postproc/render_seaweed.py <output.dir> <out.png> [index]

Reads <output.dir>/seaweed_particles.pvd (spheres as glyphs coloured by plant, joints as lines)
and, if present, <output.dir>/seaweed.pvd (LBM fields; a vertical slice coloured by speed).
`index` picks the time step (default: the last).
"""
import os

from pv_common import open_series_at, render_arguments, save_png, white_view
from paraview.simple import (ColorBy, Glyph, OpenDataFile, Render,
                             Show, Slice)

out_dir, png, index = render_arguments("seaweed_particles.pvd", "seaweed")
view = white_view()
parts, t = open_series_at(view, out_dir, "seaweed_particles.pvd", index)

fluid_pvd = os.path.join(out_dir, "seaweed.pvd")
if os.path.exists(fluid_pvd):
    fluid = OpenDataFile(fluid_pvd)
    sl = Slice(Input=fluid)
    sl.SliceType.Normal = [0, 1, 0]
    sl.SliceType.Origin = [0.5, 0.5, 0.5]
    d = Show(sl, view)
    ColorBy(d, ("CELLS", "velocity", "Magnitude"))
    d.Opacity = 0.6

lines = Show(parts, view)
lines.LineWidth = 2.0
ColorBy(lines, ("POINTS", "plant"))
g = Glyph(Input=parts, GlyphType="Sphere")
g.ScaleArray = ["POINTS", "radius"]
g.ScaleFactor = 2.0
g.GlyphMode = "All Points"
gd = Show(g, view)
ColorBy(gd, ("POINTS", "plant"))
view.ResetCamera()
view.CameraPosition = [0.5, -1.6, 0.9]
view.CameraFocalPoint = [0.5, 0.5, 0.45]
view.CameraViewUp = [0, 0, 1]
Render(view)
save_png(view, png)
print("wrote", png, "time", t)
