#!/usr/bin/env python3
"""docs/deck-reference.md must equal `biota reference` (regenerate it with
`./build/biota reference > docs/deck-reference.md`). Usage: check_reference.py <biota> <doc>"""
import subprocess
import sys

biota, doc = sys.argv[1:3]
generated = subprocess.run([biota, "reference"], capture_output=True, text=True, check=True).stdout
with open(doc) as f:
    current = f.read()
if generated != current:
    print(f"{doc} is out of date: run `{biota} reference > {doc}`")
    sys.exit(1)
print(f"{doc} matches the config schema ({generated.count('| `')} keys)")
