// interior_texture { }: layered, inherited by CSG children, on a declared
// object's copy, transparent inside (shadow rays), reflective inside a
// transparent box, in a difference and under clipped_by
camera { location <0, 2, -7> look_at 0 }
light_source { <4, 8, -6> color rgb 1 }
#declare O = sphere { 0, 1 pigment { rgbf <1, 1, 1, 0.8> } interior_texture { pigment { rgbt <1, 0, 0, 0.5> } } }
object { O interior_texture { pigment { bozo } finish { reflection 0.5 } } translate -2 * x }
box { -1, 1 texture { pigment { rgbf 1 } } interior_texture { pigment { rgb 0 } finish { reflection 0.9 } } interior_texture { pigment { rgbt 0.5 } } }
difference { box { <1, -1, -1>, <3, 1, 1> } sphere { <2, 0, -1>, 0.8 inverse }
             pigment { rgb 1 } interior_texture { gradient y texture_map { [0 pigment { rgb 1 }] [1 pigment { rgb <0, 0, 1> }] } } }
plane { y, -1 pigment { checker } interior_texture { pigment { rgb <0, 1, 0> } } clipped_by { sphere { 0, 5 } } }
