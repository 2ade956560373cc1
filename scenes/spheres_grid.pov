// spheres_grid.pov — a 5 x 5 grid of spheres seen from above at an angle,
// each finish a step along two axes (left to right: diffuse to shiny; back
// to front: matte to reflective).  A square frame: the camera's right is
// <1, 0, 0> for a 1:1 image.
//
// Framed for 480x480 (1:1; camera right <1, 0, 0>).
#version 3.7;
#include "colors.inc"

global_settings { assumed_gamma 1.0 max_trace_level 5 }

camera {
    location <0, 9, -9>
    up <0, 1, 0>
    right <1, 0, 0>
    look_at <0, 0, 0>
    angle 33
}

light_source { <-6, 12, -6> color rgb <1, 1, 1> }
light_source { <6, 5, -10> color rgb <0.3, 0.3, 0.3> shadowless }
background { color rgb <0.1, 0.1, 0.12> }

plane { y, 0 pigment { color rgb <0.3, 0.32, 0.35> } finish { ambient 0.1 diffuse 0.7 } }

#declare Ball = sphere { <0, 0.55, 0>, 0.55 }
#declare C = color rgb <0.9, 0.3, 0.2>;

// row z = 2.4: matte
object { Ball pigment { color C } finish { diffuse 0.8 } translate <-2.4, 0, 2.4> }
object { Ball pigment { color C } finish { diffuse 0.8 specular 0.2 roughness 0.1 } translate <-1.2, 0, 2.4> }
object { Ball pigment { color C } finish { diffuse 0.7 specular 0.4 roughness 0.05 } translate <0, 0, 2.4> }
object { Ball pigment { color C } finish { diffuse 0.7 phong 0.6 phong_size 40 } translate <1.2, 0, 2.4> }
object { Ball pigment { color C } finish { diffuse 0.6 phong 0.9 phong_size 200 } translate <2.4, 0, 2.4> }
// row z = 1.2
object { Ball pigment { color rgb <0.3, 0.8, 0.3> } finish { diffuse 0.8 reflection 0.1 } translate <-2.4, 0, 1.2> }
object { Ball pigment { color rgb <0.3, 0.8, 0.3> } finish { diffuse 0.8 specular 0.2 roughness 0.1 reflection 0.1 } translate <-1.2, 0, 1.2> }
object { Ball pigment { color rgb <0.3, 0.8, 0.3> } finish { diffuse 0.7 specular 0.4 roughness 0.05 reflection 0.1 } translate <0, 0, 1.2> }
object { Ball pigment { color rgb <0.3, 0.8, 0.3> } finish { diffuse 0.7 phong 0.6 phong_size 40 reflection 0.1 } translate <1.2, 0, 1.2> }
object { Ball pigment { color rgb <0.3, 0.8, 0.3> } finish { diffuse 0.6 phong 0.9 phong_size 200 reflection 0.1 } translate <2.4, 0, 1.2> }
// row z = 0
object { Ball pigment { color rgb <0.3, 0.4, 0.9> } finish { diffuse 0.6 reflection 0.3 } translate <-2.4, 0, 0> }
object { Ball pigment { color rgb <0.3, 0.4, 0.9> } finish { diffuse 0.6 specular 0.2 roughness 0.1 reflection 0.3 } translate <-1.2, 0, 0> }
object { Ball pigment { color rgb <0.3, 0.4, 0.9> } finish { diffuse 0.6 specular 0.4 roughness 0.05 reflection 0.3 } translate <0, 0, 0> }
object { Ball pigment { color rgb <0.3, 0.4, 0.9> } finish { diffuse 0.6 phong 0.6 phong_size 40 reflection 0.3 } translate <1.2, 0, 0> }
object { Ball pigment { color rgb <0.3, 0.4, 0.9> } finish { diffuse 0.5 phong 0.9 phong_size 200 reflection 0.3 } translate <2.4, 0, 0> }
// row z = -1.2
object { Ball pigment { color rgb <0.9, 0.8, 0.2> } finish { diffuse 0.4 reflection 0.5 } translate <-2.4, 0, -1.2> }
object { Ball pigment { color rgb <0.9, 0.8, 0.2> } finish { diffuse 0.4 specular 0.2 roughness 0.1 reflection 0.5 } translate <-1.2, 0, -1.2> }
object { Ball pigment { color rgb <0.9, 0.8, 0.2> } finish { diffuse 0.4 specular 0.4 roughness 0.05 reflection 0.5 } translate <0, 0, -1.2> }
object { Ball pigment { color rgb <0.9, 0.8, 0.2> } finish { diffuse 0.4 phong 0.6 phong_size 40 reflection 0.5 } translate <1.2, 0, -1.2> }
object { Ball pigment { color rgb <0.9, 0.8, 0.2> } finish { diffuse 0.3 phong 0.9 phong_size 200 reflection 0.5 } translate <2.4, 0, -1.2> }
// row z = -2.4: mirrors
object { Ball pigment { color rgb <0.8, 0.8, 0.85> } finish { ambient 0 diffuse 0.1 reflection 0.85 } translate <-2.4, 0, -2.4> }
object { Ball pigment { color rgb <0.8, 0.8, 0.85> } finish { ambient 0 diffuse 0.1 specular 0.2 roughness 0.1 reflection 0.85 } translate <-1.2, 0, -2.4> }
object { Ball pigment { color rgb <0.8, 0.8, 0.85> } finish { ambient 0 diffuse 0.1 specular 0.4 roughness 0.05 reflection 0.85 } translate <0, 0, -2.4> }
object { Ball pigment { color rgb <0.8, 0.8, 0.85> } finish { ambient 0 diffuse 0.1 phong 0.6 phong_size 40 reflection 0.85 } translate <1.2, 0, -2.4> }
object { Ball pigment { color rgb <0.8, 0.8, 0.85> } finish { ambient 0 diffuse 0.1 phong 0.9 phong_size 200 reflection 0.85 } translate <2.4, 0, -2.4> }
