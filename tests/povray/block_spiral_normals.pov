// crosscheck: full 99.5
// brick, hexagon, checker, spiral1 and spiral2 as normals (the slope of
// their values: the block patterns' 0, 1, 2 unwaved, the spirals' through
// their triangle wave), with their amounts (`hexagon 1.6`, `spiral1 5,
// 1.6`), brick_size and mortar; and brick and hexagon choosing textures
// (`hexagon texture { } texture { } texture { }`).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 0, -9> look_at 0 }
light_source { <3, 5, -8> color rgb 1 }
light_source { <-6, 3, -3> color rgb 0.35 }
#declare F = finish { phong 0.6 phong_size 30 }
box { <-4.3, 1.2, 0>, <-1.5, 3.2, 1> pigment { rgb 0.8 } normal { brick 0.75 scale 0.08 } finish { F } }
box { <-1.4, 1.2, 0>, <1.4, 3.2, 1> pigment { rgb <0.9, 0.7, 0.5> } normal { brick brick_size <1, 0.4, 0.7> mortar 0.1 bump_size 2 scale 0.7 rotate 20 * z } finish { F } }
sphere { <2.9, 2.2, 0>, 1 pigment { rgb <0.5, 0.8, 0.9> } normal { checker 1.2 scale 0.3 } finish { F } }
sphere { <-3, 0, 0>, 1.1 pigment { rgb <0.7, 0.9, 0.5> } normal { hexagon 1.6 scale 0.25 rotate <-70, 10, 0> } finish { F } }
box { <-1.4, -1.1, 0>, <1.4, 1.1, 1> texture { hexagon texture { pigment { rgb 0.2 } } texture { pigment { rgb <0.9, 0.3, 0.2> } finish { F } } texture { pigment { rgb <0.9, 0.9, 0.2> } normal { bumps 0.6 scale 0.1 } } rotate -90 * x scale 0.3 } }
sphere { <3, 0, 0>, 1.1 texture { brick texture { pigment { rgb 0.9 } } texture { pigment { rgb <0.6, 0.2, 0.1> } normal { dents 1 scale 0.2 } } scale 0.15 } }
box { <-4.3, -3.2, 0>, <-1.5, -1.2, 1> pigment { rgb 0.9 } normal { spiral1 5, 1.6 scale 0.6 translate <-2.9, -2.2, 0> } finish { F } }
box { <-1.4, -3.2, 0>, <1.4, -1.2, 1> pigment { rgb 0.9 } normal { spiral2 3 0.8 scale 0.5 translate <0, -2.2, 0> } finish { F } }
box { <1.5, -3.2, 0>, <4.3, -1.2, 1> pigment { rgb 0.9 } normal { spiral1 -2 bump_size 1 turbulence 0.2 sine_wave scale 0.5 translate <2.9, -2.2, 0> } finish { F } }
