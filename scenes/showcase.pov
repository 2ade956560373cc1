// showcase.pov — the csgtrace showcase: every kind of primitive, every CSG
// operator that matters, glass (refraction), a mirror (reflection) and
// shadows, in one picture.
//
// Framed for 640x480 (4:3; the camera's right is the default 1.33).
//   povray +W640 +H480 scenes/showcase.pov
//   build/csgtrace render scenes/showcase.pov -o showcase.png --width 640 --height 480
//
// What is in it, left to right:
//   - a glass lens: the intersection of two spheres (a biconvex lens), ior 1.5
//   - a mirror: a thin box with reflection 0.9, behind the other objects
//   - a die: a rounded cube (box intersected with a sphere) minus 21 pip spheres
//   - a glass sphere, ior 1.5, in front of a red cone
//   - a pipe (cylinder minus cylinder), an open cylinder and a cone
//   - a floor plane (slightly reflective)
#version 3.7;
#include "colors.inc"

global_settings {
    assumed_gamma 1.0
    max_trace_level 8
    ambient_light rgb <1, 1, 1>
}

camera {
    location <0.4, 3.4, -9>
    look_at <0.2, 0.9, 0>
    angle 55
}

light_source { <-6, 10, -8> color rgb <1, 1, 1> }
light_source { <7, 6, -5> color rgb <0.35, 0.35, 0.4> shadowless }

background { color rgb <0.55, 0.7, 0.9> }

#declare Glass_Finish = finish { ambient 0 diffuse 0.05 specular 0.6 roughness 0.005 reflection 0.08 }
#declare Glass = texture {
    pigment { color rgbf <0.97, 1, 0.98, 0.94> }
    finish { Glass_Finish }
}
#declare Glass_Interior = interior { ior 1.5 }
#declare Plastic = finish { ambient 0.12 diffuse 0.7 phong 0.6 phong_size 60 }

// The floor.
plane {
    y, 0
    pigment { color rgb <0.5, 0.47, 0.42> }
    finish { ambient 0.12 diffuse 0.75 reflection 0.12 }
}

// The mirror, standing at the back, turned towards the scene.
box {
    <-2.2, 0, -0.06>, <2.2, 3.2, 0.06>
    pigment { color rgb <0.85, 0.88, 0.9> }
    finish { ambient 0 diffuse 0.05 reflection 0.9 specular 0.3 }
    rotate <0, -25, 0>
    translate <-1.4, 0, 3.4>
}
// Its frame (a union of four bars), sharing the mirror's placement.
union {
    box { <-2.35, -0.01, -0.1>, <-2.2, 3.35, 0.1> }
    box { <2.2, -0.01, -0.1>, <2.35, 3.35, 0.1> }
    box { <-2.35, 3.2, -0.1>, <2.35, 3.35, 0.1> }
    box { <-2.35, -0.01, -0.1>, <2.35, 0.12, 0.1> }
    pigment { color rgb <0.35, 0.2, 0.1> }
    finish { Plastic }
    rotate <0, -25, 0>
    translate <-1.4, 0, 3.4>
}

// The lens: the intersection of two spheres, standing on edge on a small cylinder.
intersection {
    sphere { <0, 0, -1.45>, 1.8 }
    sphere { <0, 0, 1.45>, 1.8 }
    texture { Glass }
    interior { Glass_Interior }
    rotate <0, 35, 0>
    translate <-2.9, 1.2, -0.4>
}
cylinder {
    <0, 0, 0>, <0, 0.17, 0>, 0.35
    pigment { color rgb <0.2, 0.2, 0.25> }
    finish { Plastic }
    translate <-2.9, 0, -0.4>
}

// The die: a rounded cube minus its pips (opposite faces add up to 7).
#declare Pip = sphere { <0, 0, 0>, 0.17 }
#declare P = 0.42;   // pip offset from the face centre
#declare F = 1.07;   // pip centre distance from the die centre (just outside the face)
difference {
    intersection {
        box { <-1, -1, -1>, <1, 1, 1> }
        sphere { <0, 0, 0>, 1.38 }
        pigment { color rgb <0.95, 0.93, 0.88> }
    }
    // 1: bottom
    object { Pip translate <0, -F, 0> }
    // 6: top
    object { Pip translate <-P, F, -P> }
    object { Pip translate <-P, F, 0> }
    object { Pip translate <-P, F, P> }
    object { Pip translate <P, F, -P> }
    object { Pip translate <P, F, 0> }
    object { Pip translate <P, F, P> }
    // 2: front
    object { Pip translate <-P, P, -F> }
    object { Pip translate <P, -P, -F> }
    // 5: back
    object { Pip translate <-P, P, F> }
    object { Pip translate <P, P, F> }
    object { Pip translate <0, 0, F> }
    object { Pip translate <-P, -P, F> }
    object { Pip translate <P, -P, F> }
    // 3: left
    object { Pip translate <-F, P, -P> }
    object { Pip translate <-F, 0, 0> }
    object { Pip translate <-F, -P, P> }
    // 4: right
    object { Pip translate <F, P, P> }
    object { Pip translate <F, P, -P> }
    object { Pip translate <F, -P, P> }
    object { Pip translate <F, -P, -P> }
    pigment { color rgb <0.05, 0.05, 0.1> }
    finish { Plastic }
    scale 0.75
    rotate <0, -32, 0>
    translate <0.1, 0.75, -0.6>
}

// A glass sphere in front of a red cone.
sphere {
    <0, 0, 0>, 0.8
    texture { Glass }
    interior { Glass_Interior }
    translate <2.0, 0.8, -1.9>
}
cone {
    <0, 0, 0>, 0.7, <0, 2.4, 0>, 0
    pigment { color rgb <0.85, 0.12, 0.1> }
    finish { Plastic }
    translate <2.4, 0, 0.8>
}

// A pipe (a cylinder minus a thinner one), an open cylinder and a cone.
difference {
    cylinder { <0, 0, 0>, <0, 1.1, 0>, 0.5 }
    cylinder { <0, -0.1, 0>, <0, 1.2, 0>, 0.38 }
    pigment { color rgb <0.15, 0.45, 0.85> }
    finish { Plastic }
    translate <4.0, 0, -0.3>
}
cylinder {
    <0, 0, 0>, <0, 1.6, 0>, 0.35 open
    pigment { color rgb <0.95, 0.75, 0.1> }
    finish { Plastic }
    translate <0.9, 0, 1.7>
}
cone {
    <0, 0, 0>, 0.45, <0, 0.9, 0>, 0.15
    pigment { color rgb <0.2, 0.7, 0.25> }
    finish { Plastic }
    translate <-1.3, 0, -2.0>
}
