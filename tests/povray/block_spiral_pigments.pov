// The block patterns brick and hexagon (their default colours, colours
// given, pigments given, brick_size and mortar, turbulence) and the spiral
// patterns spiral1 and spiral2 (their arms, the triangle wave, another
// wave, turbulence, which they read a second time themselves), as
// POV-Ray 3.7's pattern.cpp computes them.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 0, -9> look_at 0 }
light_source { <3, 5, -8> color rgb 1 }
#declare M = color_map { [0 rgb <0.1, 0.1, 0.3>] [0.5 rgb <0.9, 0.6, 0.2>] [1 rgb 1] }
box { <-4.3, 1.2, 0>, <-1.5, 3.2, 1> pigment { brick scale 0.08 } }
box { <-1.4, 1.2, 0>, <1.4, 3.2, 1> pigment { brick rgb <0.9, 0.9, 0.8>, rgb <0.5, 0.1, 0> brick_size <1, 0.4, 0.7> mortar 0.06 scale 0.7 rotate 20 * z } }
box { <1.5, 1.2, 0>, <4.3, 3.2, 1> pigment { brick pigment { gradient x color_map { M } } pigment { bozo scale 0.3 } brick_size 0.6 mortar 0.1 turbulence 0.2 } }
sphere { <-3, 0, 0>, 1.1 pigment { hexagon scale 0.25 rotate <-70, 10, 0> } }
box { <-1.4, -1.1, 0>, <1.4, 1.1, 1> pigment { hexagon rgb 0.1, rgb <0.9, 0.3, 0.2> rgb <0.9, 0.9, 0.2> rotate -90 * x scale 0.3 translate <0.1, -0.4, 0> } }
sphere { <3, 0, 0>, 1.1 pigment { hexagon pigment { rgb <0.2, 0.4, 0.9> } pigment { granite color_map { M } } rotate -90 * x scale 0.4 turbulence 0.3 } }
box { <-4.3, -3.2, 0>, <-1.5, -1.2, 1> pigment { spiral1 5 color_map { M } scale 0.6 translate <-2.9, -2.2, 0> } }
box { <-1.4, -3.2, 0>, <1.4, -1.2, 1> pigment { spiral2 3 color_map { M } scale 0.5 translate <0, -2.2, 0> } }
box { <1.5, -3.2, 0>, <4.3, -1.2, 1> pigment { spiral1 -2 color_map { M } sine_wave frequency 2 turbulence 0.3 octaves 3 scale 0.5 translate <2.9, -2.2, 0> } }
