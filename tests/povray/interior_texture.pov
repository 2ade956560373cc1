// crosscheck: full 99.5
// interior_texture { }: what a ray meeting a surface from inside sees
// (POV-Ray's normaldirection > 0: the solid's outward normal, a
// complemented primitive's reversed, along the ray): spheres opened by
// clipped_by, a transparent box whose inside mirrors (infinitybox.pov's),
// a union passing it to its children, a difference's carved face, and the
// shadow rays, filtered by the interior texture where they leave a surface.
#version 3.7;
global_settings { assumed_gamma 1 max_trace_level 8 }
camera { location <0, 3, -9> look_at <0, 0.3, 0> }
light_source { <3, 8, -6> color rgb 1 }
light_source { <-6, 3, -3> color rgb 0.4 }
plane { y, -1.5 pigment { checker rgb 0.9, rgb 0.5 } }
sphere { <-3, 0, 0>, 1.3 texture { pigment { rgb <0.3, 0.5, 1> } }
         interior_texture { pigment { rgb <1, 0.6, 0> } finish { phong 0.8 } }
         clipped_by { plane { -z, 0.2 } } }
box { <-1, -1.5, -1>, <1, 0.5, 1> texture { pigment { rgbf <1, 1, 1, 1> } }
      interior_texture { pigment { rgb 0 } finish { reflection 0.8 } } no_shadow }
union { sphere { <3, 0, 0>, 1.2 } cylinder { <3, -1.5, 0>, <3, 1.5, 0>, 0.5 }
        texture { pigment { rgbt <0.9, 0.2, 0.2, 0.6> } }
        interior_texture { pigment { rgbt <0.2, 0.9, 0.2, 0.3> } normal { bumps 0.5 scale 0.1 } }
        clipped_by { plane { -z, 0.3 } } }
difference { box { <-4, 1.2, 0.5>, <4, 2.5, 1.5> } sphere { <0, 2.5, 0.2>, 0.9 }
             texture { pigment { rgb <0.8, 0.8, 0.6> } } interior_texture { pigment { rgb <0.6, 0, 0.6> } }
             clipped_by { plane { -z, -0.7 } } }
