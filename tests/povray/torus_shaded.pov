// crosscheck: full 99.9
// torus_shaded.pov: tori as written (diffuse, phong, reflection, shadows
// cast on each other and on the floor), compared with POV-Ray 3.7 by
// colour: the normals (POV-Ray's Torus::Normal) and the shadow rays
// through the torus's pieces; a spindle torus cut open (POV-Ray's
// default union mode: the spindle is inside, the cut face flat).
// Framed for 160x120.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -9> look_at <0, 0.3, 0> angle 50 }
light_source { <-4, 9, -6> color rgb 1 }
light_source { <5, 4, -3> color rgb 0.4 }
background { color rgb <0.2, 0.3, 0.45> }
plane { y, -1 pigment { checker color rgb 0.85, color rgb 0.45 } finish { diffuse 0.8 } }
torus { 1.2, 0.4 rotate x * -35 pigment { color rgb <0.9, 0.3, 0.2> } finish { phong 0.8 phong_size 60 } translate <-2.2, 0.4, 0> }
torus { 0.9, 0.3 rotate z * 70 pigment { color rgb <0.3, 0.6, 1> } finish { reflection 0.3 specular 0.5 } translate <1.6, 0.4, 0.3> }
torus { 2.5, 0.15 pigment { color rgb <1, 0.9, 0.4> } translate <0, -0.6, 2> }
difference {
    sphere { 0, 0.9 }
    torus { 0.9, 0.35 }
    rotate x * -30
    pigment { color rgb <0.5, 1, 0.6> }
    translate <0, 1.7, 2.5>
}
intersection {
    torus { 0.5, 0.8 }
    box { <-2, -2, 0>, <2, 2, 2> }
    rotate y * 25 rotate x * -20
    pigment { color rgb <1, 0.7, 0.7> }
    translate <-3.3, 2.2, 3>
}
