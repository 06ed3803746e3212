#!/usr/bin/python3
"""Compare two meshes within tolerances, for golden-mesh tests.

Same topology (same vertex count and identical triangle list): per-vertex
distances, max and RMS. Different topology: a symmetric Hausdorff distance
between the two surfaces, measured from dense point samples of each surface
(vertices, edge midpoints, face centroids) to the nearest such sample of the
other; it overestimates the true Hausdorff distance by at most half the
sample spacing, which is reported.

PLY files (ASCII or binary, with any extra vertex or face properties) are
read by a small reader here; other formats through meshio.

Tolerances are in metres, or fractions of the first mesh's bounding-box
diagonal with --relative. Prints one summary line; exit 0 equal within
tolerance, 1 different, 2 usage or unreadable input.
"""
import argparse
import json
import sys

import numpy as np

try:
    import meshio
except ImportError:  # pragma: no cover - reported as a usage problem
    print("meshdiff: error: python3-meshio is not installed (run: make deps)", file=sys.stderr)
    sys.exit(2)


PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
             "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply_elements(path):
    """Every element of a PLY file, ASCII or binary, as {name: {property:
    array}}; list properties (faces) come as an (n, 3) integer array under
    their own name (triangles only). meshio cannot read binary faces that
    carry scalar properties, which the pipeline writes for stretch maps."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError("not a PLY file")
    body_start = data.index(b"\n", end) + 1
    fmt, elements = None, []
    for line in data[:end].decode("ascii", "replace").splitlines()[1:]:
        tok = line.split()
        if not tok or tok[0] in ("comment", "obj_info"):
            continue
        if tok[0] == "format":
            fmt = tok[1]
        elif tok[0] == "element":
            elements.append((tok[1], int(tok[2]), []))
        elif tok[0] == "property":
            elements[-1][2].append(tok[1:])
    order = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(fmt)
    out = {}
    if order is None:  # ASCII
        words = data[body_start:].split()
        pos = 0
        for name, count, props in elements:
            columns = {p[-1]: [] for p in props}
            for _ in range(count):
                for prop in props:
                    if prop[0] == "list":
                        n = int(words[pos]); pos += 1
                        columns[prop[-1]].append([int(w) for w in words[pos:pos + n]]); pos += n
                    else:
                        columns[prop[-1]].append(float(words[pos])); pos += 1
            out[name] = {}
            for prop in props:
                if prop[0] == "list":
                    out[name][prop[-1]] = np.array(columns[prop[-1]], dtype=np.int64).reshape(-1, 3)
                else:
                    out[name][prop[-1]] = np.array(columns[prop[-1]], dtype=PLY_TYPES[prop[0]])
        return out
    pos = body_start
    for name, count, props in elements:
        fields = []
        for p in props:
            if p[0] == "list":
                fields += [("n", order + PLY_TYPES[p[1]]), (p[-1], order + PLY_TYPES[p[2]], (3,))]
            else:
                fields.append((p[-1], order + PLY_TYPES[p[0]]))
        dtype = np.dtype(fields)
        arr = np.frombuffer(data, dtype=dtype, count=count, offset=pos)
        # Lists: assume triangles (checked), which makes every record the same size.
        if any(p[0] == "list" for p in props) and count and not np.all(arr["n"] == 3):
            raise ValueError(f"element '{name}' has lists that are not triangles")
        pos += dtype.itemsize * count
        out[name] = {p[-1]: (arr[p[-1]].astype(np.int64) if p[0] == "list" else arr[p[-1]]) for p in props}
    return out


def read_ply(path):
    """Vertices (n, 3) and triangles (m, 3) of a PLY file."""
    elements = read_ply_elements(path)
    if "vertex" not in elements:
        raise ValueError("no vertex element")
    v = elements["vertex"]
    points = np.stack([np.asarray(v[a], dtype=np.float64) for a in "xyz"], axis=1)
    faces = np.zeros((0, 3), np.int64)
    for prop, values in elements.get("face", {}).items():
        if values.ndim == 2:
            faces = values
    return points, faces


def load(path):
    import contextlib
    import io
    import os

    if not os.path.isfile(path):
        raise SystemExit(f"meshdiff: error[input]: no such file ({path})")
    if path.lower().endswith(".ply"):
        try:
            points, faces = read_ply(path)
        except (ValueError, IndexError, KeyError, StopIteration, TypeError) as e:
            raise SystemExit(f"meshdiff: error[input]: cannot read mesh: {e} ({path})")
    else:
        # meshio prints its own complaints and may even call sys.exit on a file
        # it cannot parse; catch both and report one clear line.
        chatter = io.StringIO()
        try:
            with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
                mesh = meshio.read(path)
        except (Exception, SystemExit) as e:
            detail = str(e) if str(e) not in ("", "1") else chatter.getvalue().strip().replace("\n", "; ")
            raise SystemExit(f"meshdiff: error[input]: cannot read mesh: {detail} ({path})")
        tris = [c.data for c in mesh.cells if c.type == "triangle"]
        faces = np.concatenate(tris).astype(np.int64) if tris else np.zeros((0, 3), np.int64)
        points = np.asarray(mesh.points, dtype=np.float64)[:, :3]
    if faces.size and (faces.min() < 0 or faces.max() >= len(points)):
        raise SystemExit(f"meshdiff: error[input]: face index out of range ({path})")
    if not np.all(np.isfinite(points)):
        raise SystemExit(f"meshdiff: error[input]: non-finite coordinates ({path})")
    return points, faces


def surface_samples(points, faces):
    if len(faces) == 0:
        return points, 0.0
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    edges = np.concatenate([(a + b) / 2, (b + c) / 2, (c + a) / 2])
    samples = np.concatenate([points, edges, (a + b + c) / 3])
    spacing = float(np.max(np.linalg.norm(np.concatenate([b - a, c - b, a - c]), axis=1))) / 2
    return samples, spacing


def one_sided(from_pts, to_pts):
    from scipy.spatial import cKDTree

    dist, _ = cKDTree(to_pts).query(from_pts)
    return dist


def compare(a_path, b_path, tol, rms_tol, relative):
    va, fa = load(a_path)
    vb, fb = load(b_path)
    diag = float(np.linalg.norm(va.max(axis=0) - va.min(axis=0))) if len(va) else 0.0
    scale = diag if relative else 1.0
    max_tol, rms_limit = tol * scale, rms_tol * scale
    result = {"a": a_path, "b": b_path, "bbox_diagonal": diag, "max_tolerance": max_tol,
              "rms_tolerance": rms_limit}
    if va.shape == vb.shape and fa.shape == fb.shape and np.array_equal(fa, fb):
        d = np.linalg.norm(va - vb, axis=1)
        result.update(topology="same", max=float(d.max(initial=0.0)),
                      rms=float(np.sqrt(np.mean(d ** 2))) if len(d) else 0.0,
                      worst_vertex=int(d.argmax()) if len(d) else -1)
        equal = result["max"] <= max_tol and result["rms"] <= rms_limit
    else:
        sa, spacing_a = surface_samples(va, fa)
        sb, spacing_b = surface_samples(vb, fb)
        da, db = one_sided(sa, sb), one_sided(sb, sa)
        result.update(topology="different", vertices=[len(va), len(vb)], faces=[len(fa), len(fb)],
                      hausdorff=float(max(da.max(initial=0), db.max(initial=0))),
                      rms=float(np.sqrt(np.mean(np.concatenate([da, db]) ** 2))),
                      sample_spacing=max(spacing_a, spacing_b))
        equal = result["hausdorff"] <= max_tol and result["rms"] <= rms_limit
    result["equal"] = bool(equal)
    return result


def summary(r):
    unit = "m"
    if r["topology"] == "same":
        body = f"same topology, max {r['max']:.3g} {unit} (vertex {r['worst_vertex']}), rms {r['rms']:.3g} {unit}"
    else:
        body = (f"different topology ({r['vertices'][0]} vs {r['vertices'][1]} vertices), Hausdorff "
                f"{r['hausdorff']:.3g} {unit} (samples {r['sample_spacing']:.3g} {unit} apart), rms {r['rms']:.3g} {unit}")
    verdict = "equal within tolerance" if r["equal"] else "DIFFERENT"
    return (f"meshdiff: {verdict}: {body}; tolerance max {r['max_tolerance']:.3g} {unit}, "
            f"rms {r['rms_tolerance']:.3g} {unit} ({r['a']} vs {r['b']})")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("a", help="reference mesh (golden), OBJ or PLY")
    p.add_argument("b", help="mesh to check")
    p.add_argument("--tol", type=float, default=1e-6,
                   help="largest allowed distance (vertex or Hausdorff) [m, or fraction with --relative] (default 1e-6)")
    p.add_argument("--rms-tol", type=float, default=None,
                   help="largest allowed RMS distance [m, or fraction] (default: same as --tol)")
    p.add_argument("--relative", action="store_true",
                   help="tolerances are fractions of the first mesh's bounding-box diagonal")
    p.add_argument("--json", action="store_true", help="print the full comparison as JSON on stdout")
    try:
        args = p.parse_args(argv)
    except SystemExit as e:
        return 2 if e.code else 0
    if args.tol < 0 or (args.rms_tol is not None and args.rms_tol < 0):
        print("meshdiff: error[usage]: tolerances must not be negative", file=sys.stderr)
        return 2
    try:
        r = compare(args.a, args.b, args.tol, args.tol if args.rms_tol is None else args.rms_tol, args.relative)
    except SystemExit as e:
        print(e.code, file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(r, indent=2))
    print(summary(r), file=sys.stderr if args.json else sys.stdout)
    return 0 if r["equal"] else 1


if __name__ == "__main__":
    sys.exit(main())
