#!/usr/bin/env python3
"""Writes VTK's wavelet (vtkRTAnalyticSource) contoured at 157 -- a typical ParaView isosurface -- as .whtmesh files
that whitted_bench reads (format in bench_scenes.h: "WHTMESH1", counts, float32 positions and normals, uint32
triangle indices).

    /usr/bin/python3 gen_wavelet.py --out DIR [--sizes 60k,1m,4m]

The whole extent [-N, N]^3 sets the triangle count (the contour is resampled, not rescaled): N = 30 gives 60,092
triangles, 122 gives 1,007,456 and 243 gives 4,004,716. Only the 60k file (1.4 MB) is kept in data/benchmark/;
the others are generated at benchmark time into the results' cache folder.
"""
import argparse
import os
import struct
import sys

EXTENTS = {"60k": 30, "1m": 122, "4m": 243}
ISOVALUE = 157.0


def contour(n):
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkFiltersCore import vtkContourFilter, vtkTriangleFilter

    src = vtkRTAnalyticSource()
    src.SetWholeExtent(-n, n, -n, n, -n, n)
    con = vtkContourFilter()
    con.SetInputConnection(src.GetOutputPort())
    con.SetValue(0, ISOVALUE)
    con.ComputeNormalsOn()
    con.ComputeScalarsOff()
    tri = vtkTriangleFilter()  # the contour of image data is already triangles; this guarantees it
    tri.SetInputConnection(con.GetOutputPort())
    tri.Update()
    return tri.GetOutput()


def write_whtmesh(poly, path):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    pts = vtk_to_numpy(poly.GetPoints().GetData()).astype("<f4")
    normals = poly.GetPointData().GetNormals()
    nrm = vtk_to_numpy(normals).astype("<f4") if normals is not None else None
    polys = poly.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    conn = vtk_to_numpy(polys.GetConnectivityArray())
    if not np.all(np.diff(offsets) == 3):
        raise RuntimeError("non-triangle cells in the contour")
    tris = conn.astype("<u4").reshape(-1, 3)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(b"WHTMESH1")
        f.write(struct.pack("<4I", len(pts), len(tris), 1 if nrm is not None else 0, 0))
        f.write(np.ascontiguousarray(pts).tobytes())
        if nrm is not None:
            f.write(np.ascontiguousarray(nrm).tobytes())
        f.write(np.ascontiguousarray(tris).tobytes())
    os.replace(tmp, path)  # atomic: a concurrent reader never sees half a file
    return len(pts), len(tris)


def read_whtmesh(path):
    """Returns (positions Nx3 float32, normals Nx3 float32 or None, triangles Mx3 uint32)."""
    import numpy as np

    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"WHTMESH1":
        raise ValueError(path + " is not a WHTMESH1 file")
    nv, nt, flags, _ = struct.unpack_from("<4I", data, 8)
    off = 24
    pos = np.frombuffer(data, "<f4", nv * 3, off).reshape(nv, 3)
    off += nv * 12
    nrm = None
    if flags & 1:
        nrm = np.frombuffer(data, "<f4", nv * 3, off).reshape(nv, 3)
        off += nv * 12
    tris = np.frombuffer(data, "<u4", nt * 3, off).reshape(nt, 3)
    return pos, nrm, tris


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--sizes", default="60k,1m,4m", help="comma-separated subset of " + ",".join(EXTENTS))
    ap.add_argument("--force", action="store_true", help="regenerate existing files")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for size in [s for s in args.sizes.split(",") if s]:
        if size not in EXTENTS:
            sys.exit("unknown size %s (choose from %s)" % (size, ",".join(EXTENTS)))
        path = os.path.join(args.out, "wavelet_%s.whtmesh" % size)
        if os.path.exists(path) and not args.force:
            print("exists: %s" % path)
            continue
        nv, nt = write_whtmesh(contour(EXTENTS[size]), path)
        print("wrote %s: %d vertices, %d triangles, %.1f MB" % (path, nv, nt, os.path.getsize(path) / 1e6))


if __name__ == "__main__":
    main()
