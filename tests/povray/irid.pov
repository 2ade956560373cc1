// crosscheck: full 99.5
// finish { irid { AMOUNT thickness F turbulence V } }: POV-Ray's thin-film
// interference (ComputeIridColour) scales each light's diffuse and
// highlights colour by colour; the film's thickness varied by turbulence
// (five octaves of the scene's noise); irid_wavelength; a shadowless
// light (its diffuse scaled too), phong, specular and metallic.
#version 3.7;
global_settings { assumed_gamma 1 irid_wavelength rgb <0.25, 0.18, 0.14> }
camera { location <0, 0, -9> look_at 0 }
light_source { <3, 5, -8> color rgb 1 }
light_source { <-6, 3, -3> color rgb 0.4 shadowless }
background { rgb <0.1, 0.12, 0.2> }
sphere { <-3, 1.6, 0>, 1.3 pigment { rgb 0.7 } finish { irid { 0.5 thickness 0.5 } phong 0.6 } }
sphere { <0, 1.6, 0>, 1.3 pigment { rgb <0.4, 0.6, 0.9> } finish { irid { 0.35 thickness 2 turbulence 0.5 } specular 0.6 roughness 0.02 } }
sphere { <3, 1.6, 0>, 1.3 pigment { rgb <0.9, 0.7, 0.3> } finish { irid { 0.8 thickness 8 turbulence <1, 0, 0> } diffuse 0.8 metallic phong 1 } }
box { <-4.5, -3, 0>, <-1.6, -0.3, 1> pigment { rgb 0.8 } finish { irid { 0.4 thickness 1.3 turbulence 2 } } rotate <20, 30, 0> }
sphere { <1.5, -1.6, 0>, 1.3 pigment { rgb <0.5, 0.9, 0.5> } normal { bumps 0.4 scale 0.2 } finish { irid { 0.6 thickness 0.9 turbulence 0.3 } phong 0.5 } }
