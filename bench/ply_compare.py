#!/usr/bin/env python3
"""Compares two binary PLY clouds written by `ramtk scan` (x y z sigma quality, float32):
prints the largest absolute difference per property and how many points differ.
Usage: python3 bench/ply_compare.py A/cloud.ply B/cloud.ply"""
import sys

import numpy as np


def read(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    names = [line.split()[-1] for line in header if line.startswith("property")]
    return names, np.frombuffer(data[end:], dtype="<f4").reshape(-1, len(names))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    (na, a), (nb, b) = read(sys.argv[1]), read(sys.argv[2])
    if na != nb or a.shape != b.shape:
        print(f"different layouts: {na} {a.shape} vs {nb} {b.shape}")
        return 1
    d = np.abs(a.astype(np.float64) - b.astype(np.float64))
    for i, name in enumerate(na):
        print(f"{name:8s} max |diff| {d[:, i].max():.3g}  differing points {(d[:, i] > 0).sum()} of {len(d)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
