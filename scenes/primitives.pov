// primitives.pov — each primitive of the subset on its own: sphere, box,
// cylinder (closed and open), cone (pointed, truncated, open) and the
// plane, with translate / rotate / scale (uniform and not).
//
// Framed for 640x480 (4:3; default right 1.33).
#version 3.7;
#include "colors.inc"

global_settings { assumed_gamma 1.0 }

camera {
    location <0, 5, -11>
    look_at <0, 0.9, 0>
    angle 50
}

light_source { <-8, 14, -10> color rgb <1, 1, 1> }
light_source { <10, 8, -8> color rgb <0.25, 0.25, 0.3> }
background { color rgb <0.6, 0.75, 0.95> }

#declare Shiny = finish { ambient 0.1 diffuse 0.7 specular 0.5 roughness 0.02 }

plane { y, 0 pigment { color rgb <0.45, 0.55, 0.4> } finish { ambient 0.12 diffuse 0.8 } }

// back row
sphere { <0, 0, 0>, 1 pigment { color Red } finish { Shiny } translate <-3.5, 1, 2> }
box { <-0.8, 0, -0.8>, <0.8, 1.6, 0.8> pigment { color rgb <0.2, 0.4, 0.9> } finish { Shiny } rotate <0, 30, 0> translate <-0.8, 0, 2> }
cylinder { <0, 0, 0>, <0, 2, 0>, 0.7 pigment { color Yellow } finish { Shiny } translate <1.7, 0, 2> }
cone { <0, 0, 0>, 0.9, <0, 2.2, 0>, 0 pigment { color rgb <1, 0.5, 0.1> } finish { Shiny } translate <4, 0, 2> }

// front row
// an ellipsoid: a sphere scaled unevenly, then tilted
sphere { <0, 0, 0>, 1 scale <1, 0.5, 0.6> rotate <0, 0, 25> pigment { color Magenta } finish { Shiny } translate <-3.6, 0.8, -1> }
// a truncated cone lying on its side
cone { <-0.8, 0, 0>, 0.6, <0.8, 0, 0>, 0.3 pigment { color Cyan } finish { Shiny } rotate <0, 40, 0> translate <-1, 0.6, -1.2> }
// an open cylinder (a tube: its inside is visible)
cylinder { <0, 0, 0>, <0, 1.2, 0>, 0.6 open pigment { color rgb <0.9, 0.9, 0.9> } finish { Shiny } rotate <-35, 0, 0> translate <1.3, 0.6, -1.3> }
// an open cone (a lampshade)
cone { <0, 0, 0>, 0.8, <0, 1, 0>, 0.4 open pigment { color rgb <0.5, 0.9, 0.5> } finish { Shiny } rotate <-30, 0, 0> translate <3.6, 0.4, -1.3> }
// a flattened box: scale, then rotate about two axes
box { <-1, -1, -1>, <1, 1, 1> scale <0.5, 0.08, 0.5> rotate <30, 45, 0> pigment { color White } finish { Shiny } translate <0, 2.9, 0.5> }
