// poly.pov: POV-Ray's polynomial surfaces, quartic { <35> }, cubic { <20> }
// and poly { ORDER, <...> } (inside where the polynomial is < 0; the
// coefficients in POV-Ray's term order x^n, x^(n-1) y, x^(n-1) z, ...),
// checked against POV-Ray 3.7 by tests/crosscheck_povray.sh: a quartic
// torus (sturm), a monkey saddle (cubic) and an order-5 poly cut by boxes,
// a box minus a quartic cylinder, an inverse order-2 sphere cutting a box,
// an unbounded quartic bowl seen from outside; turned, scaled, translated.
// Framed for 160x120.
#version 3.7;

camera { location <0, 5, -12> look_at <0, 0.5, 0> angle 55 }
light_source { <5, 10, -8> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

plane { y, -2 pigment { checker color rgb 0.9, color rgb <0.3, 0.5, 0.3> } }

// (x^2 + y^2 + z^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + z^2), R = 1, r = 0.4
quartic {
    <1, 0, 0, 0, 2, 0, 0, 2, 0, -2.32, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
     1, 0, 0, 2, 0, 1.68, 0, 0, 0, 0, 1, 0, -2.32, 0, 0.7056>
    sturm
    rotate x * 60 rotate y * 20
    pigment { color rgb <1, 0.3, 0.2> }
    translate <-4, 0, 0>
}
// x^3 - 3 x y^2 - z: the monkey saddle, its underside cut by a box
intersection {
    cubic { <1, 0, 0, 0, -3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 0> }
    box { <-1, -1, -1>, <1, 1, 1> }
    rotate x * -90 scale 0.8
    pigment { color rgb <0.2, 0.6, 1> }
    translate <-1.3, 0, 0>
}
// x^5 + y^4 + z^4 - 0.5, cut by a box
intersection {
    poly { 5, <1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
               0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1,
               0, 0, 0, -0.5> }
    box { <-1.2, -1.2, -1.2>, <1.2, 1.2, 1.2> }
    rotate y * 30
    pigment { color rgb <1, 1, 0.3> }
    translate <1.5, 0, 0>
}
// a box minus the quartic cylinder x^4 + y^4 - 0.1 (along z)
difference {
    box { <-1, -1, -0.5>, <1, 1, 0.5> }
    quartic { <1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
               1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -0.1> }
    rotate y * 25
    pigment { color rgb <0.5, 0.8, 1> }
    translate <4.2, 0, 0>
}
// a box minus an inverse sphere of order 2 (x^2 + y^2 + z^2 - 1): the
// part of the box inside the sphere, scaled
difference {
    box { <-1, -1, -1>, <1, 1, 1> }
    poly { 2, <1, 0, 0, 0, 1, 0, 0, 1, 0, -1> inverse scale 1.3 }
    pigment { color rgb <0.3, 1, 0.8> }
    translate <-2, 2.8, 3>
}
// x^4 + z^4 - y: above it, a bowl, unbounded upward
quartic {
    <1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
     0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 1, 0, 0, 0, 0>
    scale <1.5, 1, 1.5>
    pigment { color rgb <0.6, 1, 0.4> }
    translate <2, 1.5, 6>
}
