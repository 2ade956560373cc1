#!/usr/bin/env python3
"""Writes a wide CSG scene (issue #39): a box combined with N small spheres,
as `difference` (box minus spheres), `intersection` (box and a union of the
spheres, a union run) or `union` (inside an inverse: complements).
usage: wide_scene.py OP N OUT.pov"""
import random
import sys

op, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
r = random.Random(39)
spheres = ''.join('  sphere { <%.4f,%.4f,%.4f>, %.4f pigment { color rgb <0.2,0.6,1> } }\n'
                  % (r.uniform(-11, 11), r.uniform(-11, 11), r.uniform(-11, 11),
                     r.uniform(0.05, 0.3)) for _ in range(n))
box = '  box { <-10,-10,-10>, <10,10,10> pigment { color rgb <1,0.5,0.2> } }\n'
with open(out, 'w') as f:
    f.write('camera { location <0,0,-30> look_at <0,0,0> }\n'
            'light_source { <20,30,-40> color rgb <1,1,1> }\n')
    if op == 'difference':
        f.write('difference {\n' + box + spheres + '}\n')
    elif op == 'intersection':
        f.write('intersection {\n' + box + ' union {\n' + spheres + ' }\n}\n')
    else:  # the box minus an inverse union: complemented spheres under a union
        f.write('intersection {\n' + box + ' union {\n' + spheres + ' inverse }\n'
                ' sphere { <0,0,0>, 12 }\n}\n')
