// crosscheck: full 99
// POV-Ray's variable reflection: reflection { MIN, MAX } blended by
// (1 - cos)^falloff, by the Fresnel reflectance (fresnel, with an
// interior's ior; conserve_energy: what is reflected is not transmitted),
// tinted by the pigment (metallic), the reflected colour to 1 / exponent,
// reflection_exponent, and one colour in a block.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2.2, -7> look_at <0, 0.9, 0> }
light_source { <5, 9, -6> color rgb 1 }
background { rgb <0.2, 0.3, 0.5> }
plane { y, 0 pigment { checker rgb 0.9 rgb 0.15 } }
box { <-6, 0, 3>, <6, 4, 3.5> pigment { gradient x color_map { [0 rgb <1, 0.2, 0.1>] [1 rgb <0.1, 0.3, 1>] } scale 3 } }
sphere { <-2.6, 1, 0>, 1 pigment { rgb <0.8, 0.6, 0.2> } finish { reflection { 0.05, 0.9 falloff 2 } } }
sphere { <0, 1, 0>, 1 pigment { rgbf <1, 1, 1, 0.9> } finish { ambient 0 diffuse 0.1 reflection { 0, 1 fresnel on } conserve_energy } interior { ior 1.5 } }
sphere { <2.6, 1, 0>, 1 pigment { rgb <0.9, 0.7, 0.3> } finish { diffuse 0.3 reflection { 0.3, 0.7 metallic exponent 2 } } }
sphere { <-1.3, 0.45, -1.8>, 0.45 pigment { rgb <0.2, 0.8, 0.3> } finish { reflection { rgb <0.5, 0.4, 0.3> } reflection_exponent 0.5 } }
sphere { <1.3, 0.45, -1.8>, 0.45 pigment { rgb 0.3 } finish { reflection { 0.2 0.6 fresnel metallic 0.5 } } interior { ior 2 } }
