// quadric.pov: POV-Ray's quadric { <A, B, C>, <D, E, F>, <G, H, I>, J }
// (inside where A x^2 + B y^2 + C z^2 + D xy + E xz + F yz + G x + H y
// + I z + J <= 0), checked against POV-Ray 3.7 by
// tests/crosscheck_povray.sh: an ellipsoid, cylinders and a cone cut by
// boxes, a paraboloid and a hyperboloid of one sheet (the line meets its
// outside in two half-lines), turned, scaled, sheared, translated; in
// difference and intersection, and inverse.  Framed for 160x120.
#version 3.7;

camera { location <0, 5, -12> look_at <0, 0.5, 0> angle 55 }
light_source { <5, 10, -8> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

plane { y, -2 pigment { checker color rgb 0.9, color rgb <0.3, 0.5, 0.3> } }

// an ellipsoid (x^2 + 4 y^2 + 2 z^2 - 1), turned and moved
quadric { <1, 4, 2>, <0, 0, 0>, <0, 0, 0>, -1 rotate z * 30 pigment { color rgb <1, 0.3, 0.2> } translate <-4, 0, 0> }
// a cylinder along y (x^2 + z^2 - 0.25), cut by a box, sheared
intersection {
    quadric { <1, 0, 1>, <0, 0, 0>, <0, 0, 0>, -0.25 }
    box { <-1, -1, -1>, <1, 1, 1> }
    matrix <1, 0, 0, 0.3, 1, 0, 0, 0, 1, 0, 0, 0>
    pigment { color rgb <0.2, 0.6, 1> }
    translate <-1.5, 0, 0>
}
// a cone (x^2 - y^2 + z^2 with the mixed and linear terms of a shift)
intersection {
    quadric { <1, -1, 1>, <0, 0, 0>, <0, 0, 0>, 0 }
    box { <-1.5, -1.5, -1.5>, <1.5, 1.5, 1.5> }
    scale 0.6 rotate x * 20
    pigment { color rgb <1, 1, 0.3> }
    translate <1.2, 0.5, 0>
}
// a paraboloid x^2 + z^2 - y, unbounded, upside down behind
quadric { <1, 0, 1>, <0, 0, 0>, <0, -1, 0>, 0 scale <0.5, 1, 0.5> rotate z * 180 pigment { color rgb <0.6, 1, 0.4> } translate <4, 4, 6> }
// a hyperboloid of one sheet (x^2 - y^2 + z^2 - 0.3), mixed terms, cut
intersection {
    quadric { <1, -1, 1>, <0.4, 0, 0>, <0, 0, 0>, -0.3 }
    box { <-1.2, -1, -1.2>, <1.2, 1, 1.2> }
    pigment { color rgb <1, 0.5, 1> }
    translate <4, 0, 0>
}
// CSG: a box minus a cylinder along x, a sphere minus an inverse slab
difference {
    box { <-1, -0.5, -0.5>, <1, 0.5, 0.5> }
    quadric { <0, 1, 1>, <0, 0, 0>, <0, 0, 0>, -0.1 }
    rotate y * 30
    pigment { color rgb <0.5, 0.8, 1> }
    translate <-2, 2.8, 3>
}
difference {
    sphere { 0, 1 }
    quadric { <0, 1, 0>, <0, 0, 0>, <0, 0, 0>, -0.25 inverse }
    pigment { color rgb <0.3, 1, 0.8> }
    translate <1.5, 2.8, 3>
}
