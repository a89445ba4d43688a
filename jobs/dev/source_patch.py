"""Exact-text edits of a source file, applied or reverted: the mechanism of the development
patch tools in this directory (seaweed_ab_patch.py, seaweed_phase_patch.py)."""
import pathlib
import sys


def apply(path: pathlib.Path, edits, tool: str) -> None:
    """Replace each (original, instrumented) pair's original text by the instrumented one, or back
    with --revert on the command line. Every text must occur exactly once, so a tool applied
    twice, or over another tool's edits of the same lines, stops with a message and changes
    nothing."""
    text = path.read_text()
    revert = "--revert" in sys.argv[1:]
    for original, instrumented in edits:
        old, new = (instrumented, original) if revert else (original, instrumented)
        if text.count(old) != 1:
            sys.exit(f"{tool}: expected text not found once in {path}; already "
                     f"{'reverted' if revert else 'patched'}?")
        text = text.replace(old, new)
    path.write_text(text)
