// crosscheck: full 99.5
// light_source kinds: a spotlight (point_at, radius, falloff, tightness),
// a cylinder light, a parallel light, fade_distance/fade_power, an area light
// (adaptive, circular, orient) and looks_like.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 5, -9> look_at <0, 0.5, 0> }
light_source { <-3, 6, -2> color rgb <1, 0.9, 0.7> spotlight point_at <-2, 0, 1> radius 12 falloff 20 tightness 5 }
light_source { <3, 6, -2> color rgb <0.6, 0.8, 1> cylinder point_at <2.5, 0, 1> radius 0.8 falloff 1.4 tightness 2 }
light_source { <0, 10, -10> color rgb 0.3 parallel point_at <0, 0, 0> }
light_source { <0, 3, -3> color rgb 0.8 fade_distance 2 fade_power 2 }
light_source { <0, 8, 4> color rgb 0.5 area_light <2, 0, 0>, <0, 0, 2>, 5, 5 adaptive 1 circular orient
               looks_like { sphere { 0, 0.3 pigment { rgb 1 } finish { ambient 1 } } } }
plane { y, 0 pigment { rgb 0.8 } }
sphere { <-2, 1, 1>, 1 pigment { rgb <0.9, 0.5, 0.4> } }
sphere { <2.5, 1, 1>, 1 pigment { rgb <0.5, 0.9, 0.4> } }
box { <-0.6, 0, 2>, <0.6, 1.5, 3> pigment { rgb <0.5, 0.5, 0.9> } }
