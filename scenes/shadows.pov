// shadows.pov — shadows of opaque, filtering (coloured glass) and
// transmitting (clear) objects, `no_shadow`, a shadowless fill light and
// two lights casting two shadows each.
//
// Framed for 640x480 (4:3; default right 1.33).
//
// Back row: an opaque sphere, a red filtering (rgbf) sphere, a blue
// transmitting (rgbt) box, a green filter-and-transmit (rgbft) cylinder.
// Front: a sphere with no_shadow (casts none) next to an ordinary one.
#version 3.7;
#include "colors.inc"

global_settings { assumed_gamma 1.0 max_trace_level 6 }

camera {
    location <0, 4.5, -7>
    look_at <0, 0.5, 0.3>
    angle 50
}

light_source { <-3, 9, -3> color rgb <0.8, 0.8, 0.8> }
light_source { <5, 7, -2> color rgb <0.4, 0.4, 0.4> }
light_source { <0, 6, -9> color rgb <0.15, 0.15, 0.15> shadowless }
background { color rgb <0.7, 0.7, 0.75> }

plane { y, 0 pigment { color White } finish { ambient 0.1 diffuse 0.8 } }

sphere { <-3, 0.7, 1.5>, 0.7 pigment { color rgb <0.6, 0.6, 0.6> } finish { phong 0.5 } }
sphere {
    <-1, 0.7, 1.5>, 0.7
    pigment { color rgbf <1, 0.2, 0.2, 0.8> }
    finish { ambient 0 diffuse 0.1 phong 0.6 }
    interior { ior 1.3 }
}
box {
    <-0.6, 0, -0.6>, <0.6, 1.2, 0.6>
    pigment { color rgbt <0.2, 0.3, 1, 0.7> }
    finish { ambient 0.05 diffuse 0.3 }
    rotate <0, 25, 0>
    translate <1.1, 0, 1.5>
}
cylinder {
    <0, 0, 0>, <0, 1.4, 0>, 0.55
    pigment { color rgbft <0.2, 1, 0.3, 0.5, 0.3> }
    finish { ambient 0.05 diffuse 0.3 specular 0.4 }
    translate <3.1, 0, 1.5>
}

sphere { <-0.9, 0.55, -1.2>, 0.55 pigment { color Yellow } finish { phong 0.4 } no_shadow }
sphere { <0.9, 0.55, -1.2>, 0.55 pigment { color Yellow } finish { phong 0.4 } }
