#!/usr/bin/env python3
"""Stretch of a fit along the warp and along the weft.

    scripts/grain_stretch.py REST.ply DRAPED.ply [DRAPED.ply ...] [--limits WARP WEFT]

For every face, the warp is the body's vertical (+y) projected into the rest
triangle (common/cloth/cloth_energy.h, warp_direction; faces within 0.1 of
horizontal use their first edge, as the cloth model does), the weft the
in-plane perpendicular. Prints, per draped mesh, the largest and the
area-weighted 99th percentile stretch along warp and weft, |F warp| and
|F weft| with F the rest-to-draped map, as JSON. With --limits, also the
largest stretch relative to them, max(warp / WARP, weft / WEFT), what the fit
judges (cloth::face_limit_stretches). Needs numpy (Debian's python3); reads meshes with meshdiff.py's reader.
"""
import argparse
import json
import sys

import os

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshdiff  # noqa: E402  (its reader takes the project's binary PLY faces)


def read(path):
    points, faces = meshdiff.load(path)
    return np.asarray(points, dtype=float), np.asarray(faces, dtype=int)


def frames(V, F):
    x0, x1, x2 = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    e1, e2 = x1 - x0, x2 - x0
    n = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(n, axis=1)
    n /= np.linalg.norm(n, axis=1)[:, None]
    up = np.array([0.0, 1.0, 0.0])
    d = up[None, :] - (n @ up)[:, None] * n
    flat = np.linalg.norm(d, axis=1) < 0.1
    d[flat] = e1[flat]
    d /= np.linalg.norm(d, axis=1)[:, None]
    w = np.cross(n, d)
    # Rest edges in the (warp, weft) frame.
    Dm = np.stack([np.stack([(e1 * d).sum(1), (e2 * d).sum(1)], 1),
                   np.stack([(e1 * w).sum(1), (e2 * w).sum(1)], 1)], 1)  # #F x 2 x 2
    return Dm, area


def weighted_quantile(values, weights, q):
    order = np.argsort(values)
    c = np.cumsum(weights[order])
    return float(values[order][np.searchsorted(c, q * c[-1])])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("rest")
    ap.add_argument("draped", nargs="+")
    ap.add_argument("--limits", nargs=2, type=float, metavar=("WARP", "WEFT"))
    a = ap.parse_args()
    V_rest, F = read(a.rest)
    Dm, area = frames(V_rest, F)
    Dm_inv = np.linalg.inv(Dm)
    out = []
    for path in a.draped:
        V, F2 = read(path)
        if F2.shape != F.shape or not (F2 == F).all():
            sys.exit(f"grain_stretch.py: error[geometry]: {path} does not have the rest shape's faces")
        Ds = np.stack([V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]], 2)  # #F x 3 x 2
        W = Ds @ Dm_inv  # columns: w_warp, w_weft
        warp = np.linalg.norm(W[:, :, 0], axis=1)
        weft = np.linalg.norm(W[:, :, 1], axis=1)
        r = {"mesh": path,
             "max_warp": float(warp.max()), "p99_warp": weighted_quantile(warp, area, 0.99),
             "max_weft": float(weft.max()), "p99_weft": weighted_quantile(weft, area, 0.99)}
        if a.limits:
            r["max_relative_to_limits"] = float(np.maximum(warp / a.limits[0], weft / a.limits[1]).max())
        out.append(r)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
