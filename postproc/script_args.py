"""Command-line checks shared by the post-processing scripts (render_*.py under pvpython, plot_*.py
under python3): `-h`/`--help` prints the script's docstring; a usage error, a missing input file
or an image path that is not a .png is one line on stderr and exit 2 (the scripts used to end in a
traceback, or wrote a figure named after the mistyped argument). No ParaView or matplotlib here."""
import csv
import os
import sys


def script_name():
    return os.path.basename(sys.argv[0])


def fail(message):
    """One line, exit 2."""
    sys.stderr.write(f"{script_name()}: error: {message}\n")
    sys.exit(2)


def arguments(least, most=None):
    """sys.argv[1:], after `--help` (the calling script's docstring, exit 0) and a count check."""
    args = sys.argv[1:]
    if any(a in ("-h", "--help") for a in args):
        print((sys.modules["__main__"].__doc__ or "").strip())
        sys.exit(0)
    if len(args) < least or (most is not None and len(args) > most):
        usage = next((l.strip() for l in (sys.modules["__main__"].__doc__ or "").splitlines()
                      if script_name() in l), script_name())
        fail(f"expected {least}{'' if most == least else f' to {most}' if most else ' or more'} "
             f"arguments, got {len(args)}; usage: {usage}")
    return args


def png_path(path):
    """An image path that ends in .png, in a directory that exists."""
    if not path.lower().endswith(".png"):
        fail(f"the image path must end in .png, got '{path}'")
    return image_prefix(path)


def image_prefix(prefix):
    """The path the images start with (<prefix>_x.png); its directory must exist."""
    folder = os.path.dirname(prefix) or "."
    if not os.path.isdir(folder):
        fail(f"the image's directory '{folder}' does not exist")
    return prefix


def run_file(out_dir, name, scenario):
    """<out_dir>/<name>, which a `scenario` run writes; fails with one line if it is not there."""
    if not os.path.isdir(out_dir):
        fail(f"'{out_dir}' is not a directory (give the output.dir of a {scenario} run)")
    path = os.path.join(out_dir, name)
    if not os.path.isfile(path):
        fail(f"{path}: no such file (is '{out_dir}' the output.dir of a {scenario} run?)")
    return path


def labelled_runs(args, name, scenario):
    """[(label, path of <dir>/<name>)] from `label=dir` arguments."""
    runs = []
    for a in args:
        label, sep, out_dir = a.partition("=")
        if not sep or not label or not out_dir:
            fail(f"'{a}': expected <label>=<output.dir>")
        runs.append((label, run_file(out_dir, name, scenario)))
    return runs


def csv_rows(path, columns):
    """The rows of a CSV the scenario writes, as dicts; fails if a column is missing or no row is
    there yet (a run stopped before its first row)."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = [c for c in columns if c not in (reader.fieldnames or [])]
        if missing:
            fail(f"{path}: no column {', '.join(missing)} (not a file this script reads)")
        rows = list(reader)
    if not rows:
        fail(f"{path}: no rows yet")
    return rows
