#!/usr/bin/env python3
"""test_spd_subdivide.py — unit tests of bench/spd_subdivide.py (stdlib
unittest): from a tetra file of one tetrahedron (the SPD's tetra at size
1, written here), one and two subdivisions give 4 and 16 tetrahedra of
half and a quarter the size, each inside its parent's corner, their faces
turned the same way as the parent's (a homothety keeps the orientation),
every other line kept; a file whose polygons are no tetrahedra is refused.
Run: python3 bench/test_spd_subdivide.py
"""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import spd_subdivide  # noqa: E402

# The corners of tetra's solid and its faces, as the SPD files write them.
A, B, C, D = (1, 1, 1), (-1, -1, 1), (-1, 1, -1), (1, -1, -1)
TETRA1 = """b 0.078 0.361 0.753
v
from 1.02285 -3.17715 -2.17451
at -0.004103 -0.004103 0.216539
up -0.816497 -0.816497 0.816497
angle 45
hither 1
resolution 512 512
l 2 -18 -5
f 1 0.2 0.2 1 0 100000 0 0
""" + "".join("p 3\n" + "".join("%g %g %g\n" % v for v in face) + ""
              for face in [(B, C, D), (A, D, C), (A, B, D), (A, C, B)])


def normal(face):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = face
    u, v = (bx - ax, by - ay, bz - az), (cx - ax, cy - ay, cz - az)
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def unit(v):
    n = sum(x * x for x in v) ** 0.5
    return tuple(round(x / n, 12) for x in v)


class SubdivideTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.src = os.path.join(self.dir.name, "tetra1.nff")
        with open(self.src, "w") as f:
            f.write(TETRA1)

    def tearDown(self):
        self.dir.cleanup()

    def subdivided(self, k):
        out = os.path.join(self.dir.name, "out%d.nff" % k)
        run = subprocess.run([sys.executable, os.path.join(HERE, "spd_subdivide.py"), self.src,
                              str(k), out], capture_output=True, text=True, check=True)
        self.assertEqual(run.stdout.strip(), str(4 * 4 ** k))
        return spd_subdivide.read_tetra(out)

    def test_counts_sizes_and_corners(self):
        head0, (parent,) = spd_subdivide.read_tetra(self.src)
        for k in (1, 2):
            head, tetras = self.subdivided(k)
            self.assertEqual(head, head0)
            self.assertEqual(len(tetras), 4 ** k)
            for tetra in tetras:
                corners = {v for face in tetra for v in face}
                self.assertEqual(len(corners), 4)
                edge = max(abs(a - b) for p in corners for q in corners for a, b in zip(p, q))
                self.assertAlmostEqual(edge, 2 / 2 ** k)  # the parent's edge spans 2
                # inside the solid's box and nearest to one of its corners
                self.assertTrue(all(-1 <= x <= 1 for v in corners for x in v))
        _, tetras = self.subdivided(1)
        for tetra, corner in zip(tetras, sorted([A, B, C, D])):
            self.assertIn(corner, {v for face in tetra for v in face})

    def test_faces_keep_their_orientation(self):
        _, (parent,) = spd_subdivide.read_tetra(self.src)
        want = [unit(normal(face)) for face in parent]
        for k in (1, 2):
            _, tetras = self.subdivided(k)
            for tetra in tetras:
                self.assertEqual([unit(normal(face)) for face in tetra], want)

    def test_refuses_what_is_no_tetrahedra(self):
        bad = os.path.join(self.dir.name, "bad.nff")
        with open(bad, "w") as f:
            f.write(TETRA1 + "p 3\n0 0 0\n1 0 0\n0 1 0\n")
        with self.assertRaises(ValueError):
            spd_subdivide.read_tetra(bad)


if __name__ == "__main__":
    unittest.main()
