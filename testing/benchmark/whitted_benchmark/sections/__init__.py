"""The benchmark's sections, in report order. Each module has run(ctx) (measures, writes CSV files into the
results folder), report(ctx, head) (returns the section's Markdown lines from those files and appends headline
rows [comparison, Whitted, anchor, speed ratio wall, speed ratio CPU] to head) and outputs(ctx) (the files run()
promises, checked after a run)."""
from . import build, error, glyphs, mpi, paraview, pov, rays, scaling, timeseries, update, volume, vtk

MODULES = [rays, build, pov, vtk, glyphs, volume, paraview, timeseries, scaling, update, error, mpi]
NAMES = [m.__name__.rsplit(".", 1)[-1] for m in MODULES]
BY_NAME = dict(zip(NAMES, MODULES))
