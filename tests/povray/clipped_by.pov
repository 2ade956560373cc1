// clipped_by.pov: POV-Ray's clipped_by { OBJECT... } and bounded_by,
// checked against POV-Ray 3.7 by tests/crosscheck_povray.sh: the clip's
// surfaces are never seen, the ray looks into the cut object (a
// hemisphere shows its inside), the object's later transforms move the
// clip with it; several clips, an inverse clip, a clip that is CSG, an
// inverse clipped object, clipped objects inside union, difference and
// intersection (the clip also cuts the object's inside), a clipped union,
// bounded_by { clipped_by } and clipped_by { bounded_by }, and shadows
// through the cut.  Framed for 160x120.
#version 3.7;

camera { location <0, 5, -12> look_at <0, 0.5, 0> angle 60 }
light_source { <5, 10, -8> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

plane { y, -2 pigment { checker color rgb 0.9, color rgb <0.3, 0.5, 0.3> } }

// a hemisphere open towards the camera, turned after the clip
sphere { 0, 1.2 clipped_by { plane { z, 0 } } rotate y * 20 translate <-4.5, 0, 0>
         pigment { color rgb <1, 0.3, 0.2> } }
// a box cut by two clips: a sphere and an inverse cylinder
box { -1, 1
      clipped_by { sphere { 0, 1.35 } }
      clipped_by { cylinder { -2 * z, 2 * z, 0.5 inverse } }
      rotate <20, 30, 0> translate <-1.5, 0, 0> pigment { color rgb <0.2, 0.6, 1> } }
// a clip that is CSG (its transforms after the objects), on a cylinder
cylinder { -1.2 * y, 1.2 * y, 0.8
           clipped_by { difference { box { -1, 1 } sphere { <1, 1, -1>, 1 } } scale 1.1 }
           translate <1.5, 0, 0> pigment { color rgb <1, 1, 0.3> } }
// a clipped object in a difference: the clip cuts the hole too
difference {
    box { <-1, -0.8, -0.8>, <1, 0.8, 0.8> }
    sphere { <0, 0, -0.8>, 0.7 clipped_by { plane { y, 0.2 } } }
    rotate y * -25 translate <4.3, 0, 0> pigment { color rgb <1, 0.5, 1> } }
// in a union and an intersection; an inverse clipped object
union {
    sphere { 0, 0.8 clipped_by { box { -1, <1, 0.3, 1> } } }
    cone { -y, 0.2, y, 0.6 clipped_by { plane { -x, 0.1 } } translate x * 0.9 }
    translate <-3.5, 2.6, 3> pigment { color rgb <0.6, 1, 0.4> } }
intersection {
    box { -1, 1 }
    sphere { 0, 0.9 inverse clipped_by { plane { x, 0.3 } } }
    rotate y * 40 translate <0, 2.8, 4> pigment { color rgb <0.5, 0.8, 1> } }
// a clipped union (its children cut alike), and linked bounds
union {
    sphere { <-0.5, 0, 0>, 0.7 } sphere { <0.5, 0, 0>, 0.7 }
    clipped_by { plane { -y, 0 } } bounded_by { clipped_by }
    translate <3.5, 2.6, 3> pigment { color rgb <1, 0.7, 0.2> } }
torus { 0.8, 0.3 bounded_by { box { <-1.2, -0.4, -1.2>, <1.2, 0.4, 0> } } clipped_by { bounded_by }
        rotate x * -60 translate <0, -1, -3> pigment { color rgb <0.8, 0.8, 0.8> } }
