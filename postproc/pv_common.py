"""Shared set-up of the pvpython render scripts (render_*.py): a white render view and the step of
a .pvd series chosen by index. Imported from the scripts' own directory."""
import os

from paraview.simple import (GetActiveViewOrCreate, OpenDataFile, SaveScreenshot,
                             UpdatePipeline)
from script_args import arguments, fail, png_path, run_file


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
    times = times or [0.0]
    if not -len(times) <= index < len(times):
        fail(f"index {index}: {pvd_name} has {len(times)} time step(s); allowed: "
             f"{-len(times)} to {len(times) - 1}")
    t = times[index]
    UpdatePipeline(time=t, proxy=reader)
    view.ViewTime = t
    return reader, t


def render_arguments(pvd_name, scenario):
    """(output.dir, png, index) of `render_x.py <output.dir> <out.png> [index]`. A usage error, a
    missing <output.dir>/<pvd_name>, an image path that is not a .png (ParaView would only log
    'Unknown file format' and exit 0 without an image) or an index that is not an integer is one
    line and exit 2."""
    args = arguments(2, 3)
    png = png_path(args[1])
    run_file(args[0], pvd_name, scenario)
    try:
        index = int(args[2]) if len(args) > 2 else -1
    except ValueError:
        fail(f"index '{args[2]}': expected an integer (a time step; negative counts from the end)")
    return args[0], png, index


def save_png(view, png, size=(1200, 900)):
    """SaveScreenshot, then a non-zero exit if no image was written."""
    SaveScreenshot(png, view, ImageResolution=list(size))
    if not os.path.isfile(png):
        fail(f"no image written to '{png}'")
