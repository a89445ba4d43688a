"""Shared set-up of the pvpython render scripts (render_*.py): a white render view and the step of
a .pvd series chosen by index. Imported from the scripts' own directory."""
import os
import sys

from paraview.simple import (GetActiveViewOrCreate, OpenDataFile, SaveScreenshot,
                             UpdatePipeline)


def white_view(size=(1200, 900)):
    """The active render view at `size` pixels on a white background (not the palette's)."""
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = list(size)
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:  # ParaView before 5.10 has no palette switch
        pass
    view.Background = [1, 1, 1]
    return view


def open_series_at(view, out_dir, pvd_name, index):
    """Open <out_dir>/<pvd_name>, move it and the view to its time step `index` (negative counts
    from the end); returns (reader, time)."""
    reader = OpenDataFile(os.path.join(out_dir, pvd_name))
    try:
        times = [float(v) for v in reader.TimestepValues]
    except TypeError:  # a single step comes back as a number
        times = [float(reader.TimestepValues)]
    t = (times or [0.0])[index]
    UpdatePipeline(time=t, proxy=reader)
    view.ViewTime = t
    return reader, t


def png_argument(path):
    """The image path of a render script's command line; a path that is not a .png is a usage error
    (ParaView would only log 'Unknown file format' and the script would exit 0 without an image)."""
    if not path.lower().endswith(".png"):
        sys.exit(f"{os.path.basename(sys.argv[0])}: the image path must end in .png, got '{path}'")
    return path


def save_png(view, png, size=(1200, 900)):
    """SaveScreenshot, then a non-zero exit if no image was written."""
    SaveScreenshot(png, view, ImageResolution=list(size))
    if not os.path.isfile(png):
        sys.exit(f"{os.path.basename(sys.argv[0])}: no image written to '{png}'")
