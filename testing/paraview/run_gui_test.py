"""Runs a GUI playback test and fails it unless its oracle wrote "ok".

Usage: run_gui_test.py --result FILE -- <paraview command line...>
The result file is removed first; the test passes when the command exits with 0 (its playback and baseline
comparison passed) and FILE's first line then reads "ok" (gui_oracle.py's checks, run from the playback's Python shell). A
playback that never reached the oracle leaves no file, which fails.
"""
import os
import subprocess
import sys


def main():
    args = sys.argv[1:]
    if len(args) < 4 or args[0] != "--result" or args[2] != "--":
        print(__doc__)
        return 2
    result, command = args[1], args[3:]
    if os.path.exists(result):
        os.remove(result)
    code = subprocess.call(command)
    text = open(result).read() if os.path.exists(result) else ""
    print("run_gui_test: exit code %d; oracle (%s):\n%s" % (code, result, text or "no result written"), flush=True)
    if code != 0:
        return code
    return 0 if text.splitlines()[:1] == ["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
