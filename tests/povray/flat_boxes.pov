// flat_boxes.pov: boxes whose corners share a coordinate (zero thickness),
// which POV-Ray 3.7 renders as sheets seen from both sides
// (tests/crosscheck_povray.sh compares them with POV-Ray itself).
// Sheets flat in x, y and z; turned, sheared and scaled; seen from the
// front and from the back; as CSG operands (intersection, difference,
// union, merge) and beside their solids; a box flat in two axes (a
// segment) that no ray sees.  Framed for 160x120.
#version 3.7;

camera { location <0, 3, -9> look_at <0, 0.5, 0> angle 50 }
light_source { <4, 8, -6> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

// the floor: a sheet flat in y, checkered (the checker's floor(y) sits on it)
box { <-6, -1, -3>, <6, -1, 8> pigment { checker color rgb 0.9, color rgb <0.2, 0.5, 0.2> } }

// flat in z, facing the camera, and flat in x, turned to show its other side
box { <-3.5, -0.5, 0>, <-2, 1.5, 0> pigment { gradient y color_map { [0 color rgb <1, 0, 0>] [1 color rgb <1, 1, 0>] } } }
box { <0, -0.5, -1>, <0, 1.5, 1> rotate y * 60 translate <-1.2, 0, 1> pigment { checker color rgb <0, 0, 1>, color rgb 1 scale 0.5 } }

// corners given high to low, sheared by a matrix, scaled unevenly
box { <1.5, 2, 0.5>, <0.5, 1, 0.5> matrix <1, 0.3, 0, 0, 1, 0, 0.4, 0, 1, 0, 0, 0> scale <1.5, 1, 2> pigment { color rgb <0.8, 0.4, 1> } }

// CSG: the disc of a sheet inside a sphere; a sheet with a round hole; a
// solid box cut in two by a sheet (from outside: the box alone); a sheet
// in a union and in a merge with a sphere
intersection {
    box { <-1, 0, 0>, <1, 0, 2> }
    sphere { <0, 0, 1>, 0.8 }
    translate <2.2, 1.6, -1>
    pigment { color rgb <1, 0.5, 0> }
}
difference {
    box { <-1, -1, 0>, <1, 1, 0> }
    sphere { 0, 0.5 }
    rotate x * -25
    translate <2.5, 0, 1>
    pigment { color rgb <0, 0.8, 0.8> }
}
difference {
    box { <-0.5, -0.5, -0.5>, <0.5, 0.5, 0.5> pigment { color rgb <0.6, 0.6, 0.6> } }
    box { <-1, 0, -1>, <1, 0, 1> pigment { color rgb <1, 0, 1> } }
    rotate y * 30
    translate <0.8, -0.4, -2.5>
}
union {
    sphere { <0, 0, 0>, 0.4 pigment { color rgb <1, 1, 1> } }
    box { <-0.8, 0, -0.8>, <0.8, 0, 0.8> pigment { color rgb <1, 0.2, 0.2> } }
    translate <-2.4, -0.3, -2.5>
}
merge {
    sphere { <0, 0, 0>, 0.4 pigment { color rgb <0.2, 0.2, 1> } }
    box { <-0.7, -0.7, 0>, <0.7, 0.7, 0> rotate y * 20 pigment { color rgb <1, 1, 0.3> } }
    translate <-0.6, 2.4, 0.5>
}

// a segment: no ray sees it
box { <-3, 2.5, 0>, <3, 2.5, 0> pigment { color rgb 1 } }
