// crosscheck: full 99.5
// interior { fade_distance fade_power fade_color }: light through the inside
// of glass fades with the distance it crossed (fade_power 1 and 2 towards a
// fade colour, 1001: exponential, no fade_color: towards black; no
// fade_power: POV-Ray halves the light seen through, its shadow is not faded).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 3, -7> look_at <0, 0.8, 0> }
light_source { <4, 8, -6> color rgb 1 }
background { rgb <0.3, 0.35, 0.45> }
plane { y, 0 pigment { checker rgb 0.9 rgb 0.2 scale 0.7 } }
#declare G = finish { ambient 0 diffuse 0.1 }
sphere { <-2.4, 1, 0>, 1 pigment { rgbf <1, 1, 1, 0.95> } finish { G } interior { ior 1.4 fade_distance 0.6 fade_power 2 fade_color <0.9, 0.3, 0.2> } }
sphere { <0, 1, 0>, 1 pigment { rgbt <1, 1, 1, 0.9> } finish { G } interior { ior 1.2 fade_distance 1 fade_power 1001 fade_colour rgb <0.2, 0.5, 0.9> } }
box { <1.5, -0.5, -1>, <3.3, 2, 1> pigment { rgbf <0.9, 1, 0.9, 0.9> } finish { G } interior { fade_distance 0.8 fade_power 1 } rotate 20 * y }
sphere { <0.9, 0.5, -2>, 0.5 pigment { rgbf <1, 1, 1, 0.9> } finish { G } interior { ior 1.1 fade_distance 0.5 fade_color rgb <0.2, 0.9, 0.2> } }
