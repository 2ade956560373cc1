// crosscheck: full 93
// Random by nature: an area light's jitter (each grid point anywhere in
// its cell) and a finish's crand (grain: each light's diffuse term less a
// random fraction).  POV-Ray draws from its own generator, csgtrace from
// a hash of the pixel, so no pixel need match: the agreement asked (3/255
// a channel) is what the noise leaves: 96.3 % measured, where POV-Ray
// agrees with itself run to run on 97.0-97.5 % (+WT1, +WT2, again), and
// 100 % with neither jitter nor crand.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -7> look_at <0, 0.6, 0> }
light_source { <3, 7, -2>, 1 area_light 3*x, 3*z, 4, 4 adaptive 0 jitter }
light_source { <-5, 6, -5>, 0.3 }
plane { y, 0 pigment { rgb 0.8 } }
sphere { <-1.5, 1, 0>, 1 pigment { rgb <0.9, 0.5, 0.3> } finish { crand 0.05 } }
box { <0.5, 0, 0>, <2, 1.5, 1.5> pigment { rgb <0.4, 0.6, 0.9> } }
