// #38: tori (two pieces a torus in the flat scene), a spindle one, negative
// radii (inverted), sturm among the modifiers, tori in CSG
#version 3.7;
camera { location <0, 3, -8> look_at 0 }
light_source { <3, 6, -4> color rgb 1 }
torus { 1, 0.3 sturm pigment { color rgb 1 } rotate x * 30 }
torus { 0.2, 0.5 union translate <-2, 0, 0> }
torus { -1, 0.25 scale <1, 2, 1> translate <2, 0, 2> }
difference { box { -1, 1 } torus { 0.8, 0.3 sturm 0 } translate <0, 0, 3> }
intersection { torus { 3, 1e-3 } plane { x, 0 } translate <0, 1, 6> }
