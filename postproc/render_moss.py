"""Render a snapshot of a moss run (PNG) with ParaView, headless:

    postproc/headless.sh pvpython postproc/render_moss.py <output.dir> <out.png> [index]

Reads <output.dir>/moss_surface.pvd (the terrain, coloured by the day's insolation S in W/m^2,
cell data) and <output.dir>/moss.pvd (the live mosses, drawn as 1 cm cubes coloured by species:
0 bryum, 1 hypnum, 2 polytrichum). `index` picks the output day (default: the last). The camera
looks from the front, above, into the space under the roof at the back.
"""
import os

from pv_common import open_series_at, render_arguments, save_png, white_view
from paraview.simple import (ColorBy, GetColorTransferFunction, Glyph,
                             GetScalarBar, OpenDataFile, Render, Show,
                             UpdatePipeline)

out_dir, png, index = render_arguments("moss_surface.pvd", "moss")
view = white_view()
terrain, t = open_series_at(view, out_dir, "moss_surface.pvd", index)
td = Show(terrain, view)
td.SetRepresentationType("Surface")
ColorBy(td, ("CELLS", "S"))
slut = GetColorTransferFunction("S")
slut.ApplyPreset("Inferno (matplotlib)", True)
slut.RescaleTransferFunction(0.0, 120.0)
td.SetScalarBarVisibility(view, True)
bar = GetScalarBar(slut, view)
bar.Title = "S [W/m^2]"
bar.ComponentTitle = ""
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]

mosses = OpenDataFile(os.path.join(out_dir, "moss.pvd"))
UpdatePipeline(time=t, proxy=mosses)
g = Glyph(Input=mosses, GlyphType="Box")
g.ScaleArray = ["POINTS", "No scale array"]
g.ScaleFactor = 0.015  # the 1 cm moss models, drawn 1.5 times larger to be seen
g.GlyphMode = "All Points"
gd = Show(g, view)
ColorBy(gd, ("POINTS", "species"))
lut = GetColorTransferFunction("species")
lut.ApplyPreset("Set1", True) if hasattr(lut, "ApplyPreset") else None
lut.RescaleTransferFunction(0.0, 2.0)

view.CameraPosition = [1.0, 2.6, 4.2]
view.CameraFocalPoint = [1.0, 0.4, 0.8]
view.CameraViewUp = [0.0, 1.0, 0.0]
Render(view)
save_png(view, png)
print("wrote", png, "day", t / 86400.0)
