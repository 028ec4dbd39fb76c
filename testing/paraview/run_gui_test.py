"""Runs a GUI playback test and fails it unless its oracle wrote "ok".

Usage: run_gui_test.py --result FILE [--expect-oracle-failure TEXT] -- <paraview command line...>
The result file is removed first; the test passes when the command exits with 0 (its playback and baseline
comparison passed) and FILE's first line then reads "ok" (gui_oracle.py's checks, run from the playback's Python
shell). A playback that never reached the oracle leaves no file, which fails.
With --expect-oracle-failure (a negative control, e.g. WHITTED_GUI_ORACLE_PERTURB set): the test passes only if the
oracle ran, failed, and one of its failed checks contains TEXT (the exit code does not count: the perturbation
fails the baseline capture too).
"""
import os
import subprocess
import sys


def main():
    args = sys.argv[1:]
    expect = None
    if len(args) > 4 and args[2] == "--expect-oracle-failure":
        expect = args[3]
        args = args[:2] + args[4:]
    if len(args) < 4 or args[0] != "--result" or args[2] != "--":
        print(__doc__)
        return 2
    result, command = args[1], args[3:]
    if os.path.exists(result):
        os.remove(result)
    code = subprocess.call(command)
    text = open(result).read() if os.path.exists(result) else ""
    print("run_gui_test: exit code %d; oracle (%s):\n%s" % (code, result, text or "no result written"), flush=True)
    if expect is not None:
        failed = [line for line in text.splitlines() if line.startswith("FAIL  ")]
        hit = text.startswith("FAILED") and any(expect in line for line in failed)
        print("run_gui_test: negative control, oracle failure containing '%s': %s" % (expect, "seen" if hit else
                                                                                        "NOT seen"), flush=True)
        return 0 if hit else 1
    if code != 0:
        return code
    return 0 if text.splitlines()[:1] == ["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
