#!/usr/bin/python3
"""Tests of scripts/meshdiff.py on meshes built here: equal, perturbed within
and beyond tolerance, different topology, unreadable input."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import meshio
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
MESHDIFF = os.path.join(HERE, "..", "meshdiff.py")


def grid(n, size=1.0):
    xs = np.linspace(0, size, n + 1)
    pts = np.array([[x, 0.0, z] for z in xs for x in xs])
    tris = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = a + n + 1, b + n + 1
            tris += [[a, c, d], [a, d, b]]
    return pts, np.array(tris)


def write(path, pts, tris):
    meshio.write(path, meshio.Mesh(pts, [("triangle", tris)]), binary=True) if path.endswith(".ply") \
        else meshio.write(path, meshio.Mesh(pts, [("triangle", tris)]))


def run(*args):
    r = subprocess.run([sys.executable, MESHDIFF, *args], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


class MeshDiffTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="meshdiff_")
        self.addCleanup(shutil.rmtree, self.dir, ignore_errors=True)
        self.pts, self.tris = grid(10)
        self.a = os.path.join(self.dir, "a.ply")
        write(self.a, self.pts, self.tris)

    def path(self, name, pts, tris):
        p = os.path.join(self.dir, name)
        write(p, pts, tris)
        return p

    def test_identical_meshes_are_equal(self):
        code, out = run(self.a, self.path("b.obj", self.pts, self.tris))
        self.assertEqual(code, 0, out)
        self.assertIn("same topology, max 0 m", out)

    def test_perturbation_within_and_beyond_tolerance(self):
        moved = self.pts.copy()
        moved[17, 1] += 1e-4
        b = self.path("b.ply", moved, self.tris)
        self.assertEqual(run(self.a, b, "--tol", "2e-4")[0], 0)
        code, out = run(self.a, b, "--tol", "5e-5")
        self.assertEqual(code, 1, out)
        self.assertIn("DIFFERENT", out)
        self.assertIn("vertex 17", out)
        # Relative tolerance: 1e-4 m on a sqrt(2) m diagonal is 7.1e-5 of it.
        self.assertEqual(run(self.a, b, "--tol", "8e-5", "--relative")[0], 0)
        self.assertEqual(run(self.a, b, "--tol", "6e-5", "--relative")[0], 1)

    def test_different_topology_uses_hausdorff(self):
        pts, tris = grid(7)
        b = self.path("b.ply", pts, tris)
        code, out = run(self.a, b, "--tol", "0.1")
        self.assertEqual(code, 0, out)
        self.assertIn("different topology", out)
        lifted = pts.copy()
        lifted[:, 1] += 0.05
        code, out = run(self.a, self.path("c.ply", lifted, tris), "--tol", "0.01")
        self.assertEqual(code, 1, out)

    def test_binary_ply_with_face_and_vertex_fields(self):
        import struct
        pts, tris = self.pts, self.tris
        header = ("ply\nformat binary_little_endian 1.0\n"
                  f"element vertex {len(pts)}\nproperty double x\nproperty double y\nproperty double z\n"
                  "property double w\n"
                  f"element face {len(tris)}\nproperty list uchar int vertex_indices\nproperty double stretch\n"
                  "end_header\n").encode()
        body = b"".join(struct.pack("<4d", *p, 1.0) for p in pts)
        body += b"".join(struct.pack("<B3id", 3, *t, 1.05) for t in tris)
        b = os.path.join(self.dir, "fields.ply")
        with open(b, "wb") as f:
            f.write(header + body)
        code, out = run(self.a, b)
        self.assertEqual(code, 0, out)
        self.assertIn("same topology, max 0 m", out)

    def test_unreadable_input_is_exit_2(self):
        bad = os.path.join(self.dir, "bad.ply")
        with open(bad, "w") as f:
            f.write("not a mesh")
        code, out = run(self.a, bad)
        self.assertEqual(code, 2, out)
        self.assertIn("error[input]", out)
        self.assertEqual(run(self.a)[0], 2)


if __name__ == "__main__":
    unittest.main()
