#!/usr/bin/env python3
"""spd_subdivide.py — the SPD's tetra scene at sizes beyond the shipped
files, for bench/spd_big.sh: tetra N+K from tetra N.

Haines' tetra generator draws a tetrahedron as four half-size corner
tetrahedra, recursively; size N has 4^(N-1) tetrahedra of 4 triangles
(4^N triangles), each tetrahedron written as 4 consecutive `p 3`
polygons.  So each tetrahedron of a file, replaced by its four corner
tetrahedra (every vertex v of its faces mapped to (v + corner) / 2, a
homothety, which keeps the faces' orientation), gives the next size; the
view, light, material and background lines are kept.  tetra6 subdivided
twice is the shipped tetra8 triangle for triangle (checked: the same set
of oriented triangles; the order of the tetrahedra differs).

Usage: spd_subdivide.py IN.nff K OUT.nff   (writes OUT, prints its count)
"""
import sys


def read_tetra(path):
    """The file's lines other than polygons, and its tetrahedra (each the
    4 faces of 3 vertices)."""
    head, faces = [], []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].split()[:2] == ["p", "3"]:
            faces.append([tuple(float(x) for x in lines[i + j].split()) for j in (1, 2, 3)])
            i += 4
        else:
            if lines[i].strip():
                head.append(lines[i])
            i += 1
    if len(faces) % 4:
        raise ValueError("%s: %d triangles, not tetrahedra of 4" % (path, len(faces)))
    return head, [faces[k:k + 4] for k in range(0, len(faces), 4)]


def subdivide(tetra):
    """The 4 corner tetrahedra of half the size, in corner order."""
    corners = sorted({v for face in tetra for v in face})
    if len(corners) != 4:
        raise ValueError("a tetrahedron with %d corners" % len(corners))
    return [[[tuple((a + b) / 2 for a, b in zip(v, c)) for v in face] for face in tetra]
            for c in corners]


def write_tetra(path, head, tetras):
    with open(path, "w") as out:
        out.write("\n".join(head) + "\n")
        for tetra in tetras:
            for face in tetra:
                out.write("p 3\n" + "".join("%.17g %.17g %.17g\n" % v for v in face))


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__.strip().splitlines()[-1])
    head, tetras = read_tetra(argv[1])
    for _ in range(int(argv[2])):
        tetras = [t for tetra in tetras for t in subdivide(tetra)]
    write_tetra(argv[3], head, tetras)
    print(len(tetras) * 4)


if __name__ == "__main__":
    main(sys.argv)
