"""The built binary's disassembly, function by function, for the codegen checks in this folder.
Exits 77 (CTest: skipped) off x86-64 or without objdump."""
import platform
import re
import shutil
import subprocess
import sys


def functions(binary):
    """Yields (demangled function name, its instruction lines) for every function of `binary`."""
    if platform.machine() not in ("x86_64", "AMD64") or not shutil.which("objdump"):
        print("not x86-64 or no objdump: skipped")
        sys.exit(77)
    dis = subprocess.run(["objdump", "-d", "-C", "--no-show-raw-insn", binary],
                         capture_output=True, text=True, check=True).stdout
    name, lines = None, []
    for line in dis.splitlines():
        head = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
        if head:
            if name is not None:
                yield name, lines
            name, lines = head.group(1), []
        elif name is not None:
            lines.append(line)
    if name is not None:
        yield name, lines
