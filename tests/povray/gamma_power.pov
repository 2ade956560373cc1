// crosscheck: full 100
// assumed_gamma 2.2 in a 3.7 scene: the colours are decoded by the power
// 2.2 before the file's sRGB curve; srgb colours are decoded by the sRGB
// curve then encoded by the working gamma; the background's transmit
// darkens it (3.7 composes it over black).
#version 3.7;
global_settings { assumed_gamma 2.2 }
camera { location <0, 1, -4> look_at 0 }
light_source { <5, 5, -5> color rgb 1 }
background { rgbt <0.2, 0.3, 0.4, 0.5> }
sphere { <-0.6, 0, 0>, 0.8 pigment { srgb <0.8, 0.4, 0.2> } finish { phong 0.5 } }
sphere { <0.9, 0, 0.5>, 0.7 pigment { rgbf <0.3, 0.9, 0.5, 0.6> } }
plane { y, -1 pigment { checker rgb 0.3 rgb 0.7 } }
