"""The Whitted Ray Trace view in pvbatch under MPI (testing/paraview/bench_still.py): 1 rank x 1 thread, 2 ranks x
1 thread (image split between ranks, geometry replicated) and 1 rank x all threads, alternating."""
import os
import re
import statistics

from ..markdown import commands_block, md_table
from ..runner import REPO, XVFB, fresh, paraview_env, paraview_tools, read_csv, write_csv

CONFIGS = [(1, 1), (2, 1), (1, 0)]  # (ranks, tracing threads per rank; 0 = all cores)


def run(ctx):
    c = ctx.cfg
    path = fresh(ctx.path("mpi.csv"))
    tools = paraview_tools(ctx, "mpi", mpi=True)
    if not tools:
        return
    plugin, pvpath, pvbatch, mpirun = tools
    script = os.path.join(REPO, "testing", "paraview", "bench_still.py")
    rows = []
    for rep in range(c["mpi_reps"]):
        for ranks, threads in CONFIGS:
            # --bind-to none: Open MPI binds each rank to one core by default (np <= 2), which would leave the
            # 1 rank x all threads case one core (the tracer follows the affinity mask)
            cmd = XVFB + [mpirun, "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "--mca", "btl",
                          "self,vader", "-x", "DISPLAY", "-x", "PYTHONPATH", "-np", str(ranks), pvbatch, script,
                          "--plugin", plugin, "--extent", str(c["mpi_extent"]), "--size", c["mpi_size"], "--threads",
                          str(threads), "--frames", str(c["mpi_frames"])]
            _, text, _ = ctx.runner.run(cmd, "mpi %d rank %s threads rep %d" % (ranks, threads or "all", rep),
                                        env=paraview_env(pvpath), timeout=900)
            still = re.search(r"first frame ([0-9.]+) s, still frame median ([0-9.]+) s", text)
            cpu = re.search(r"CPU seconds per frame and rank: ([0-9. ]+) \(load average ([0-9.]+)\)", text)
            tris = re.search(r"([0-9]+) triangles", text)
            if not (still and cpu and tris):
                raise RuntimeError("unexpected output of bench_still.py:\n" + text[-2000:])
            cpus = [float(v) for v in cpu.group(1).split()]
            w, h = c["mpi_size"].split("x")
            rows.append(dict(ranks=ranks, threads_per_rank=threads or ctx.threads, rep=rep,
                             triangles=int(tris.group(1)), width=int(w), height=int(h),
                             first_seconds=float(still.group(1)), still_seconds=float(still.group(2)),
                             cpu_seconds_per_rank=" ".join("%.3f" % v for v in cpus),
                             cpu_seconds_total=sum(cpus), load=float(cpu.group(2))))
    write_csv(path, rows)


def outputs(ctx):
    return ["mpi.csv"]


def report(ctx, head):
    mpi = read_csv(ctx.path("mpi.csv"))
    if not mpi:
        return []
    r0 = min(mpi, key=lambda r: r["ranks"])  # one rank: the triangle count without ghost cells
    L = ["\n## ParaView view under MPI (pvbatch)\n",
         "The Whitted Ray Trace view in `pvbatch` (`testing/paraview/bench_still.py`): the wavelet contoured to %d "
         "triangles as Whitted Surface (reflectance 0.2) with ParaView's light kit and shadows, %dx%d. Under MPI "
         "the geometry is replicated to every rank and the image split between ranks (IceT composites by depth). "
         "Still frame = Render() wall time on rank 0 after a 2-degree camera turn, median of %d frames, then "
         "median over %d repetitions run alternately with the other configurations; first frame = delivery + "
         "conversion + BVH build + trace. CPU time per frame is read from /proc for every rank.\n" % (
             r0["triangles"], r0["width"], r0["height"], ctx.cfg["mpi_frames"], max(r["rep"] for r in mpi) + 1)]
    med, tab = {}, []
    for ranks, threads in dict.fromkeys((r["ranks"], r["threads_per_rank"]) for r in mpi):
        rs = [r for r in mpi if r["ranks"] == ranks and r["threads_per_rank"] == threads]
        per_rank = [[float(v) for v in str(r["cpu_seconds_per_rank"]).split()] for r in rs]
        med[(ranks, threads)] = statistics.median(r["still_seconds"] for r in rs)
        tab.append(["%d x %d" % (ranks, threads), "%.3f" % med[(ranks, threads)],
                    "%.2f" % statistics.median(r["first_seconds"] for r in rs),
                    " + ".join("%.3f" % statistics.median(p[i] for p in per_rank) for i in range(ranks)),
                    "%.2f" % statistics.median(r["load"] for r in rs)])
    base = med.get((1, 1))
    for row, key in zip(tab, med):
        row.append("%.2f" % (base / med[key]) if base else "")
    L.append(md_table(["ranks x threads per rank", "still frame s", "first frame s", "CPU s per frame (rank 0 + 1)",
                       "load average", "speed-up vs 1 x 1"], tab))
    two = med.get((2, 1))
    hybrid = [k for k in med if k[0] == 1 and k[1] == 2]
    if base and two:
        L.append("\n2 ranks x 1 thread against 1 rank x 1 thread: **%.2fx**%s.\n" % (
            base / two, "; against 1 rank x 2 threads (the same cores, threads instead of ranks): %.2fx" % (
                med[hybrid[0]] / two) if hybrid else ""))
    L.append(commands_block(ctx, "mpi"))
    return L
