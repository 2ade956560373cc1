// crosscheck: full 99.5
// average: a pigment's pigment_map entries weighted by their values over
// their sum (nested patterns, turbulence and transforms of the average
// itself), and a texture's texture_map entries (each lit, a filtering one
// among them: the shadow it casts is averaged too).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -7> look_at <0, 0.6, 0> }
light_source { <4, 8, -5>, 1 }
light_source { <-5, 6, -3>, 0.4 }
plane { y, 0
  pigment { average
    pigment_map { [1 checker rgb <0.9, 0.9, 0.2>, rgb <0.1, 0.2, 0.6>]
                  [0.5 gradient x color_map { [0 rgb 0] [1 rgb <1, 0.3, 0.2>] } scale 1.3]
                  [0.25 rgb <0.2, 0.8, 0.3>] }
    turbulence 0.2 scale 0.8 rotate y * 20 } }
sphere { <-1.8, 1, 0>, 1
  pigment { average pigment_map { [1 rgb x] [3 bozo scale 0.3] [2 rgb <0, 0.3, 1>] } } }
sphere { <0.6, 0.8, -0.5>, 0.8
  texture { average
    texture_map { [1 pigment { rgb <1, 0.6, 0.2> } finish { phong 0.9 phong_size 30 }]
                  [2 pigment { rgb <0.3, 0.6, 1> filter 0.6 } finish { diffuse 0.8 }]
                  [1 pigment { wood scale 0.2 } finish { specular 0.5 }] } } }
box { <1.8, 0, 0.5>, <3, 1.6, 1.7>
  texture { average texture_map { [1 pigment { rgb 1 }] [1 pigment { rgb <0.8, 0.2, 0.2> }] } }
  rotate y * 30 }
