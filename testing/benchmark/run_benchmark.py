#!/usr/bin/env python3
"""Whitted benchmark: ray throughput and BVH build against Embree 3 (default and robust mode), whole frames against
POV-Ray 3.7, VTK's own OpenGL renderer and ParaView's Render View, scaling, update cost, error against run time,
and the ParaView view under MPI. Writes a Markdown report, CSV files and PNG plots into one folder and prints the
headline table.

    /usr/bin/python3 testing/benchmark/run_benchmark.py --build-dir build/vtk --out results          # full
    /usr/bin/python3 testing/benchmark/run_benchmark.py --build-dir build/vtk --out results --quick  # CI

--build-dir: a configured build tree of the project (whitted_bench is built there first) or an empty folder (the
benchmark is then configured standalone from testing/benchmark/). --bench PATH uses an existing whitted_bench.
Meshes too large to keep in the repository (1M and 4M triangles) are generated with VTK into --cache (default
<out>/cache) and reused by later runs.

The paraview and mpi sections run pvbatch; they need the ParaView plugin build (found next to --build-dir as
../paraview and ../pvprefix, as ./whitted.sh lays them out, or given with --paraview-plugin and
--pv-pythonpath) and are skipped with a note otherwise.

Every timing is a median of repeated runs after a warm-up; every ratio compares measurements of the same run
(ours and each anchor alternate run by run). Speed ratios are written ours/anchor: > 1 means Whitted is faster.
The code is the whitted_benchmark package next to this file (runner, one module per section, plots, report).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from whitted_benchmark.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(__doc__))
