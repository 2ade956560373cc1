// csg_ops.pov — every CSG operator of the subset, alone and nested, with
// `inverse`, on one row of pedestals.
//
// Framed for 640x480 (4:3; default right 1.33).
//
// Left to right, back row:
//   union         two overlapping clear red spheres: the inner surfaces
//                 show through
//   intersection  box ∩ sphere (a rounded cube)
//   difference    box minus sphere minus cylinder (first child minus the others)
//   merge         the same two spheres, merged: no inner surfaces
// Front row:
//   intersection with an `inverse` child: a sphere ∩ (inverse box) is the
//                 same as sphere minus box
//   nested        (sphere ∪ cylinder) minus (box ∩ sphere), then rotated
//   difference of a difference: a cube with a slot, minus a sphere bite
#version 3.7;
#include "colors.inc"

global_settings { assumed_gamma 1.0 }

camera {
    location <0, 3.6, -7.2>
    look_at <0, 0.3, 0>
    angle 58
}

light_source { <-5, 12, -9> color rgb <1, 1, 1> }
light_source { <8, 5, -6> color rgb <0.3, 0.3, 0.3> shadowless }
background { color rgb <0.08, 0.1, 0.16> }

#declare Matte = finish { ambient 0.15 diffuse 0.75 phong 0.4 phong_size 30 }

plane { y, 0 pigment { color rgb <0.4, 0.4, 0.42> } finish { ambient 0.15 diffuse 0.7 } }

// union
union {
    sphere { <-0.35, 0, 0>, 0.6 }
    sphere { <0.35, 0, 0>, 0.6 }
    pigment { color rgbt <1, 0.2, 0.1, 0.6> }
    finish { Matte }
    translate <-3.6, 0.7, 1.5>
}

// intersection
intersection {
    box { <-0.6, -0.6, -0.6>, <0.6, 0.6, 0.6> }
    sphere { <0, 0, 0>, 0.8 }
    pigment { color rgb <0.2, 0.7, 0.3> }
    finish { Matte }
    rotate <0, 30, 0>
    translate <-1.2, 0.6, 1.5>
}

// difference: the first child minus every other child
difference {
    box { <-0.6, -0.6, -0.6>, <0.6, 0.6, 0.6> }
    sphere { <0, 0.6, -0.6>, 0.5 pigment { color Yellow } }
    cylinder { <-1, 0, 0>, <1, 0, 0>, 0.25 }
    pigment { color rgb <0.2, 0.4, 0.9> }
    finish { Matte }
    rotate <0, -30, 0>
    translate <1.2, 0.6, 1.5>
}

// merge: like union, without the inner surfaces
merge {
    sphere { <-0.35, 0, 0>, 0.6 }
    sphere { <0.35, 0, 0>, 0.6 }
    pigment { color rgbt <1, 0.2, 0.1, 0.6> }
    finish { Matte }
    translate <3.6, 0.7, 1.5>
}

// intersection with an inverse child = difference
intersection {
    sphere { <0, 0, 0>, 0.7 }
    box { <-1, 0, -1>, <0, 1, 0> inverse }
    pigment { color Cyan }
    finish { Matte }
    rotate <0, -30, 0>
    translate <-2.6, 0.7, -1.7>
}

// nested: (sphere ∪ cylinder) minus (box ∩ sphere)
difference {
    union {
        sphere { <0, 0.7, 0>, 0.6 }
        cylinder { <0, 0, 0>, <0, 0.7, 0>, 0.35 }
    }
    intersection {
        box { <-0.2, 0.3, -1>, <1, 1.5, 1> }
        sphere { <0.2, 0.8, 0>, 0.55 }
        pigment { color White }
    }
    pigment { color rgb <0.9, 0.3, 0.5> }
    finish { Matte }
    rotate <0, 60, 0>
    translate <0, 0, -1.7>
}

// a difference nested in a difference
difference {
    difference {
        box { <-0.6, 0, -0.6>, <0.6, 1.2, 0.6> }
        box { <-0.15, 0.4, -1>, <0.15, 1.3, 1> }
    }
    sphere { <0.6, 1.2, -0.6>, 0.45 }
    pigment { color rgb <0.95, 0.85, 0.6> }
    finish { Matte }
    rotate <0, 25, 0>
    translate <2.6, 0, -1.7>
}
