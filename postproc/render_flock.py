"""Render a snapshot of the flock (PNG) with ParaView, headless:

    postproc/headless.sh pvpython postproc/render_flock.py <output.dir> <out.png> [index]

Reads <output.dir>/flock_boids.pvd (boids as spheres coloured by state: 0 grounded, 1 flying,
2 fleeing after an avalanche, 3 predator) and, if present, <output.dir>/flock_sandpile.pvd (the
L^3 sandpile heights, drawn as a small translucent cube beside the box). `index` picks the time
step (default: the last).
"""
import os

from pv_common import open_series_at, render_arguments, save_png, white_view
from paraview.simple import (ColorBy, GetColorTransferFunction, Glyph,
                             OpenDataFile, Render, Show, UpdatePipeline)

out_dir, png, index = render_arguments("flock_boids.pvd", "flock")
view = white_view()
boids, t = open_series_at(view, out_dir, "flock_boids.pvd", index)

g = Glyph(Input=boids, GlyphType="Sphere")
g.ScaleArray = ["POINTS", "No scale array"]
g.ScaleFactor = 0.6
g.GlyphMode = "All Points"
gd = Show(g, view)
ColorBy(gd, ("POINTS", "state"))
lut = GetColorTransferFunction("state")
lut.RescaleTransferFunction(0.0, 3.0)

pile = os.path.join(out_dir, "flock_sandpile.pvd")
if os.path.exists(pile):
    lattice = OpenDataFile(pile)
    UpdatePipeline(time=t, proxy=lattice)
    d = Show(lattice, view)
    d.SetRepresentationType("Surface")
    ColorBy(d, ("CELLS", "height"))
    d.Opacity = 0.5

view.ResetCamera()
Render(view)
save_png(view, png)
print("wrote", png, "time", t)
