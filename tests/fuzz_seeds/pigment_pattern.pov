// pigment_pattern { }: nested in itself, in a pigment map, a normal, a
// texture_map's pattern; an empty body (black)
camera { location <0, 1, -6> look_at 0 }
light_source { <4, 8, -6> color rgb 1 }
#declare P = pigment { bozo pigment_map { [0.3 pigment_pattern { wrinkles } color_map { [0 rgb 1] [1 rgb <1, 0, 0>] }] [0.7 leopard scale 0.1] } }
sphere { <-1.5, 0, 0>, 1 pigment { pigment_pattern { pigment_pattern { P scale 0.5 } turbulence 0.4 } } normal { pigment_pattern { P } 2 } }
sphere { <1.5, 0, 0>, 1 texture { pigment_pattern { P } texture_map { [0 pigment { rgb 1 }] [1 pigment { rgb <0, 0, 1> } normal { pigment_pattern { } } ] } } }
plane { y, -1 pigment { pigment_pattern { checker pigment { P } pigment { brick } } pigment_map { [0 P] [1 rgb 0.5] } } }
