"""The ending the benchmark smoke scripts share: on failures, the command's output and one FAIL
line each, exit 1; else the one-line summary."""
import sys


def finish(output, failures, summary):
    if failures:
        print(output)
        print("\n".join("FAIL: " + f for f in failures))
        sys.exit(1)
    print(summary)
