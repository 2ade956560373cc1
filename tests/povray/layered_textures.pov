// crosscheck: full 99.5
// Layered textures (texture { } texture { }: the last written on top, seen
// through the filter and transmit of those above), texture_map (a pattern
// blending whole textures, with normals and reflection inside), checker of
// textures, material { texture interior }, a declared layered texture, a
// pigment on an object with a texture (it edits the top layer).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 3.5, -7> look_at <0, 0.7, 0> }
light_source { <4, 8, -6> color rgb 1 }
light_source { <-6, 3, -3> color rgb 0.3 }
background { rgb <0.1, 0.12, 0.2> }
#declare Red = texture { pigment { rgb <0.9, 0.2, 0.2> } finish { phong 0.8 } }
#declare Blue = texture { pigment { rgb <0.2, 0.3, 0.9> } normal { bumps 0.5 scale 0.1 } finish { reflection 0.3 } }
#declare Spots = texture { pigment { rgb <0.3, 0.8, 0.3> } }
                 texture { pigment { bozo color_map { [0 rgbt 1] [0.5 rgbt 1] [0.6 rgb <0.9, 0.8, 0.1>] } scale 0.3 } finish { phong 1 } }
sphere { <-2.2, 1, 0>, 0.9 texture { gradient x texture_map { [0.3 Red] [0.7 Blue] } scale 0.5 rotate 20 * z } }
sphere { <0, 1, 0>, 0.9 texture { Spots } }
sphere { <2.2, 1, 0>, 0.9 material { texture { Blue } interior { ior 1.3 } } }
sphere { <-1.1, 0.5, -1.8>, 0.5 texture { pigment { rgbf <1, 1, 1, 0.6> } } texture { pigment { rgbt <0.9, 0.1, 0.1, 0.5> } finish { phong 0.5 } } pigment { rgbt <0.1, 0.1, 0.9, 0.4> } }
sphere { <1.1, 0.5, -1.8>, 0.5 texture { leopard texture_map { [0 pigment { rgb <1, 0.8, 0.2> }] [1 Spots] } scale 0.2 } }
plane { y, 0 texture { checker texture { Red } texture { pigment { rgb 0.8 } normal { wrinkles 0.4 } } scale 1.5 } }
