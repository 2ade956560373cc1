// crosscheck: full 99.5
// fog { }: a constant fog (its colour's filter and transmit: the least light
// left), a ground fog (fog_type 2, fog_offset, fog_alt, a tilted up) with
// turbulence; no fog inside a non-hollow object (the glass sphere), fog inside
// a hollow one; rays that hit nothing see the fog's colour.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2, -8> look_at <0, 1, 0> }
light_source { <5, 10, -5> color rgb 1 }
background { rgb <0.2, 0.3, 0.5> }
fog { distance 30 color rgbt <0.7, 0.7, 0.75, 0.1> }
fog { fog_type 2 distance 8 color rgbf <0.9, 0.8, 0.7, 0.3> fog_offset 0 fog_alt 0.5
      turbulence <0.4, 0.3, 0.4> octaves 4 omega 0.6 lambda 2.2 turb_depth 0.4 up <0, 1, 0.1> rotate 5 * x }
plane { y, 0 pigment { checker rgb 0.8 rgb 0.3 } }
sphere { <-2.5, 1, 2>, 1 pigment { rgb <0.9, 0.3, 0.2> } }
sphere { <2.5, 1, 8>, 1 pigment { rgb <0.2, 0.8, 0.3> } }
sphere { <-0.8, 1, -1>, 0.9 pigment { rgbf <1, 1, 1, 0.9> } interior { ior 1 } }
sphere { <1.2, 1, -1>, 0.9 pigment { rgbf <1, 1, 1, 0.9> } interior { ior 1 } hollow }
box { <-1, 0, 14>, <1, 6, 15> pigment { rgb <0.8, 0.8, 0.2> } }
