#!/usr/bin/env python3
"""Simulation behind README.md's note on the sample sequence: the RMS error of a pixel's mean over random
integrands (a straight edge at a random angle and offset; a disc of radius 0.05-0.25 at a random centre), and the
ratio of the half-difference estimate's mean to the mean squared error, for progressive pixels' samples:
  grid+R2: today's (a 2x2 jittered grid, then the R2 sequence with a random offset; halves: the grid's checkerboard,
           then alternate samples), as in core/image/sampling.h
  sobol:   one Owen-scrambled Sobol (0,2)-sequence (halves: alternate pairs)
  2xsobol: two independently scrambled Sobol sequences, one per half (interleaved)
usage: python3 sample_sequences.py [trials]   (numpy; a few minutes at the default 1500)"""
import sys
import numpy as np

TRIALS = int(sys.argv[1]) if len(sys.argv) > 1 else 1500
rng = np.random.default_rng(2)
A1, A2 = 0.7548776662466927, 0.5698402909980532
V1 = [1 << 31]
for k in range(1, 32):
    V1.append(V1[-1] ^ (V1[-1] >> 1))


def sobol2(i):
    x = y = 0
    k = 0
    while i:
        if i & 1:
            x ^= 1 << (31 - k)
            y ^= V1[k]
        i >>= 1
        k += 1
    return x, y


def owen(v, seed, bits=16):
    out, prefix = 0, 0
    for d in range(bits):
        b = (v >> (31 - d)) & 1
        out |= (b ^ (hash((seed, d, prefix)) & 1)) << (31 - d)
        prefix = (prefix << 1) | b
    return (out + int(rng.integers(0, 1 << (32 - bits)))) / 2 ** 32


def owen_sobol(n):
    seeds = (int(rng.integers(1 << 30)), int(rng.integers(1 << 30)))
    return np.array([(owen(x, seeds[0]), owen(y, seeds[1])) for x, y in map(sobol2, range(n))]).reshape(-1, 2)


def grid_r2(n):
    g = np.array([((i % 2 + rng.random()) / 2, (i // 2 + rng.random()) / 2) for i in range(4)])
    ox, oy = rng.random(), rng.random()
    r = np.array([((ox + A1 * k) % 1, (oy + A2 * k) % 1) for k in range(n - 4)]).reshape(-1, 2)
    return np.vstack([g, r])


def sobol(n):
    return owen_sobol(n)


def sobol_halves(n):
    a, b = owen_sobol((n + 1) // 2), owen_sobol(n // 2)
    return np.array([a[s >> 1] if s % 2 == 0 else b[s >> 1] for s in range(n)])


HALF = {"grid+R2": lambda s: ((s % 2 + s // 2) & 1) if s < 4 else ((s - 4) & 1),
        "sobol": lambda s: (s >> 1) & 1, "2xsobol": lambda s: s & 1}
PATTERNS = {"grid+R2": grid_r2, "sobol": sobol, "2xsobol": sobol_halves}
G = np.stack(np.meshgrid((np.arange(256) + 0.5) / 256, (np.arange(256) + 0.5) / 256), -1).reshape(-1, 2)


def study(name, n, kind):
    r2 = np.random.default_rng(9)
    err, est = [], []
    half = np.array([HALF[name](s) for s in range(n)])
    for _ in range(TRIALS):
        if kind == "edge":
            th, c = r2.random() * 2 * np.pi, r2.random() - 0.5
            f = lambda p: (((p[:, 0] - 0.5) * np.cos(th) + (p[:, 1] - 0.5) * np.sin(th)) < c).astype(float)
        else:
            cx, cy = r2.random(2)
            r = 0.05 + 0.2 * r2.random()
            f = lambda p: (((p[:, 0] - cx) ** 2 + (p[:, 1] - cy) ** 2) < r * r).astype(float)
        v = f(PATTERNS[name](n))
        a, b = v[half == 0], v[half == 1]
        err.append((v.mean() - f(G).mean()) ** 2)
        est.append((a.mean() - b.mean()) ** 2 * len(a) * len(b) / n / n)
    return np.sqrt(np.mean(err)), np.mean(est) / np.mean(err)


for kind in ("edge", "disc"):
    for n in (4, 8, 16, 32):
        print(kind, n, "  ".join("%s RMS %.4f estimate/MSE %.2f" % ((name,) + study(name, n, kind)) for name in PATTERNS),
              flush=True)
