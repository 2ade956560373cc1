// #38: crand, an area light's jitter (circular, orient, adaptive), average
// pigments (nested, zero weights, with turbulence) and average textures
#version 3.7;
camera { location <0, 3, -8> look_at 0 }
light_source { <3, 6, -4> color rgb 1 area_light x, z, 3, 3 adaptive 2 jitter circular orient }
light_source { <-3, 6, -4> color rgb 0.5 area_light 2*x, 2*z, 1, 4 jitter }
plane { y, -1 pigment { average pigment_map { [0 rgb 1] [0 rgb x] } } finish { crand 0.4 } }
sphere { 0, 1 pigment { average turbulence 0.3 pigment_map { [1 checker rgb 1, rgb 0]
  [2 average pigment_map { [-1 rgb y] [3 bozo scale 0.2] }] } scale 0.5 } finish { crand 1e9 } }
box { -1, 1 texture { average texture_map { [1 pigment { rgbf <1, 0, 0, 0.9> }]
  [2 pigment { rgb z } finish { crand 0.2 phong 1 }] } } translate <2.5, 0, 0> }
