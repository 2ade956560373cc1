// crosscheck: full 99.5
// normal { }: POV-Ray's normal-only patterns (bumps, dents, ripples, waves,
// wrinkles, quilted), any pattern's slope (granite, marble with turbulence,
// gradient), bump_size, accuracy, transforms (a non-uniform scale and a
// rotation of the normal, of the object after it), #default { normal { } }.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -7> look_at <0, 0.6, 0> }
light_source { <4, 8, -6> color rgb 1 }
light_source { <-6, 3, -3> color rgb 0.35 }
background { rgb <0.1, 0.12, 0.2> }
#declare F = finish { phong 0.6 phong_size 30 }
sphere { <-2.4, 1, 1>, 0.8 pigment { rgb <0.9, 0.6, 0.3> } normal { bumps 0.6 scale 0.15 } finish { F } }
sphere { <-0.8, 1, 1>, 0.8 pigment { rgb <0.3, 0.6, 0.9> } normal { dents 1.5 scale 0.3 } finish { F } }
sphere { <0.8, 1, 1>, 0.8 pigment { rgb <0.5, 0.9, 0.4> } normal { waves 0.5 frequency 3 scale <0.3, 0.6, 0.3> rotate 30 * z } finish { F } }
sphere { <2.4, 1, 1>, 0.8 pigment { rgb <0.9, 0.4, 0.6> } normal { wrinkles bump_size 0.7 scale 0.25 } finish { specular 0.5 } scale <1, 1.3, 1> }
sphere { <-1.6, 0.7, -1>, 0.7 pigment { rgb 0.8 } normal { granite 0.5 accuracy 0.05 scale 0.6 } finish { F } }
sphere { <0, 0.7, -1>, 0.7 pigment { rgb <0.8, 0.8, 0.3> } normal { marble 0.8 turbulence 0.6 scale 0.4 } finish { F } rotate 20 * y }
sphere { <1.6, 0.7, -1>, 0.7 pigment { rgb <0.4, 0.8, 0.8> } normal { gradient y 1.2 scale 0.2 sine_wave } finish { F } }
box { <-4, -0.2, 2.2>, <4, 0.3, 3.5> pigment { rgb <0.8, 0.75, 0.7> } normal { quilted 0.8 control0 0.5 control1 0.9 scale 0.5 } }
#default { normal { ripples 0.4 frequency 2 scale 0.8 } }
plane { y, 0 pigment { checker rgb 0.75 rgb 0.45 scale 1.5 } }
