// crosscheck: full 99.5
// pigment_pattern { PIGMENT }: the grey (0.297 r + 0.589 g + 0.114 b) of a
// pigment as a pattern's value: through a colour map, a pigment map, as a
// normal's slope (`normal { pigment_pattern { P } 3 }`, a brick's), with
// its own transforms and the outer pattern's turbulence; a plain colour
// (the brick moved off the box's faces: a mortar boundary on a face is
// decided by the rounding of the hit point, float against double).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 0, -9> look_at 0 }
light_source { <3, 5, -8> color rgb 1 }
light_source { <-6, 3, -3> color rgb 0.35 }
#declare P = pigment { bozo pigment_map { [0.3 wrinkles color_map { [0 rgb <1, 0.2, 0>] [1 rgb <0, 0.5, 1>] } scale 0.3]
                                        [0.7 leopard scale 0.05 color_map { [0 rgb 0] [1 rgb <0.2, 1, 0.4>] }] } scale 0.8 }
#declare F = finish { phong 0.6 phong_size 30 }
sphere { <-3, 1.6, 0>, 1.3 pigment { P } finish { F } }
sphere { <0, 1.6, 0>, 1.3 pigment { pigment_pattern { P } } finish { F } }
sphere { <3, 1.6, 0>, 1.3 pigment { pigment_pattern { P } color_map { [0 rgb <0.2, 0, 0>] [0.5 rgb <1, 0.3, 0.1>] [1 rgb <1, 1, 0.6>] } turbulence 0.3 } finish { F } }
box { <-4.5, -3, 0>, <-1.6, -0.3, 1> pigment { rgb 0.9 } normal { pigment_pattern { brick rgb 1, rgb <0.5, 0.1, 0> scale 0.1 translate <0.013, 0.021, 0.007> } , 0.5 } finish { F } }
sphere { <0, -1.6, 0>, 1.3 pigment { rgb <0.9, 0.8, 0.6> } normal { pigment_pattern { P } 3 rotate 20 * y } finish { F } }
sphere { <3, -1.6, 0>, 1.3 pigment { pigment_pattern { rgb <0.8, 0.4, 0.1> } pigment_map { [0 rgb 0] [0.5 checker rgb 1, rgb <0, 0, 1> scale 0.3] } } finish { F } }
