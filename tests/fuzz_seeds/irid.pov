// finish { irid { } } with its thickness and turbulence (a vector), global
// irid_wavelength, a shadowless light, layered and mapped textures
global_settings { irid_wavelength rgb <0.25, 0.18, 0.14> noise_generator 1 }
camera { location <0, 1, -6> look_at 0 }
light_source { <4, 8, -6> color rgb 1 }
light_source { <-4, 2, -6> color rgb 0.5 shadowless }
sphere { <-1.5, 0, 0>, 1 pigment { rgb 0.6 } finish { irid { 0.5 thickness 0.4 turbulence <0.7, 1, 1> } phong 0.8 crand 0.1 } }
sphere { <1.5, 0, 0>, 1 texture { pigment { rgb 0.6 } finish { irid { 2 thickness -3 } specular 1 } } texture { pigment { rgbt <1, 0, 0, 0.6> } finish { irid { 0.1 } } } }
plane { y, -1 texture { checker texture { finish { irid { 0.9 thickness 1e30 turbulence 1e30 } } } texture { pigment { rgb 1 } } } }
