// torus.pov: POV-Ray's torus (csg/device/poly_solve.h: a Sturm sequence
// finds the quartic's roots), checked against POV-Ray 3.7 by
// tests/crosscheck_povray.sh: tori turned, scaled unevenly and sheared;
// seen edge on and through the hole; a thin one far away; a spindle torus
// (major radius below the minor: POV-Ray's default union); tori as CSG
// operands (intersection, difference, merge with a sphere, inverse).
// Framed for 160x120.
#version 3.7;

camera { location <0, 4, -12> look_at <0, 0.5, 0> angle 55 }
light_source { <5, 10, -8> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

plane { y, -1.5 pigment { checker color rgb 0.9, color rgb <0.3, 0.5, 0.3> } }

// plain, then turned to be seen through its hole, then edge on
torus { 1, 0.35 pigment { color rgb <1, 0.3, 0.2> } translate <-4, 0, 0> }
torus { 1, 0.3 sturm rotate x * 80 pigment { color rgb <0.2, 0.6, 1> } translate <-1.3, 0.5, 0> }
torus { 0.9, 0.25 rotate z * 90 rotate y * 10 pigment { color rgb <1, 1, 0.2> } translate <1.3, 0.3, 0> }
// scaled unevenly and sheared
torus { 0.8, 0.3 scale <1.5, 0.7, 1> matrix <1, 0.3, 0, 0, 1, 0, 0.2, 0, 1, 0, 0, 0>
        pigment { color rgb <0.6, 1, 0.4> } translate <4, 0, 0> }
// thin and far away
torus { 3, 0.05 rotate x * -20 pigment { color rgb 1 } translate <0, 2, 30> }
// a spindle torus (R < r)
torus { 0.3, 0.6 pigment { color rgb <1, 0.5, 1> } translate <-4, 0.2, 4> }

// CSG
intersection {
    torus { 1, 0.4 }
    box { <-2, -1, -2>, <0.3, 1, 2> }
    rotate x * -30
    pigment { color rgb <1, 0.6, 0.1> }
    translate <-1.5, 2.8, 2>
}
difference {
    box { <-1, -0.3, -1>, <1, 0.3, 1> }
    torus { 0.7, 0.25 }
    rotate x * -35
    pigment { color rgb <0.5, 0.8, 1> }
    translate <1.5, 2.8, 2>
}
merge {
    torus { 0.8, 0.3 }
    sphere { <0.8, 0, 0>, 0.4 }
    rotate x * -50
    pigment { color rgb <0.9, 0.9, 0.5> }
    translate <4, 2.5, 3>
}
difference {
    sphere { 0, 1 }
    torus { 1, 0.4 inverse }
    pigment { color rgb <0.3, 1, 0.8> }
    translate <0, -0.4, 4>
}
