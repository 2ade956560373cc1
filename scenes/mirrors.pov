// mirrors.pov — inter-reflections: two parallel mirrors facing each other
// (the "infinite corridor", cut by max_trace_level), a mirror sphere
// between them and coloured objects that appear many times.
//
// Framed for 640x480 (4:3; default right 1.33).
#version 3.7;
#include "colors.inc"

global_settings { assumed_gamma 1.0 max_trace_level 12 }

camera {
    location <-0.9, 1.7, -6>
    look_at <0.6, 1.2, 0.5>
    angle 62
}

light_source { <0, 8, -4> color rgb <1, 1, 1> }
light_source { <-2, 3, -6> color rgb <0.3, 0.3, 0.3> shadowless }
background { color rgb <0.35, 0.45, 0.6> }

#declare Mirror = texture {
    pigment { color rgb <0.9, 0.9, 0.92> }
    finish { ambient 0 diffuse 0.05 reflection 0.88 }
}

plane { y, 0 pigment { color rgb <0.4, 0.3, 0.25> } finish { ambient 0.15 diffuse 0.7 } }

// two mirrors facing each other across x, like the walls of a corridor
box { <-2.3, 0, -4>, <-2.2, 3, 4> texture { Mirror } }
box { <2.2, 0, -4>, <2.3, 3, 4> texture { Mirror } }

// a mirror ball on a short pillar
sphere { <0, 1.6, 0.8>, 0.7 texture { Mirror } }
cylinder { <0, 0, 0.8>, <0, 0.95, 0.8>, 0.2 pigment { color rgb <0.3, 0.3, 0.3> } finish { ambient 0.1 diffuse 0.6 phong 0.5 } }

// coloured things to be reflected
sphere { <-1.5, 0.5, -0.5>, 0.5 pigment { color Red } finish { ambient 0.1 diffuse 0.7 phong 0.8 phong_size 80 } }
box { <-0.4, 0, -0.4>, <0.4, 0.8, 0.4> pigment { color rgb <0.1, 0.6, 0.2> } finish { ambient 0.1 diffuse 0.7 } rotate <0, 35, 0> translate <1.6, 0, -0.8> }
cone { <0, 0, 0>, 0.4, <0, 1.3, 0>, 0 pigment { color rgb <0.2, 0.4, 1> } finish { ambient 0.1 diffuse 0.7 phong 0.5 } translate <0.3, 0, -1.6> }
