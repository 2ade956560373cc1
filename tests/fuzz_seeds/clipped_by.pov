// #38: clipped_by and bounded_by: several lists, transforms inside the
// braces and after them, inverse clips, a clipped declared object, CSG
// clips and clipped CSG, the linked forms bounded_by { clipped_by } and
// clipped_by { bounded_by }, a bound alone
#version 3.7;
camera { location <0, 3, -8> look_at 0 }
light_source { <3, 6, -4> color rgb 1 }
#declare Half = sphere { 0, 1 clipped_by { plane { y, 0 } } }
object { Half rotate x * 30 pigment { color rgb 1 } }
box { -1, 1 clipped_by { sphere { 0, 1.3 } cylinder { -2 * z, 2 * z, 0.4 inverse } scale 1.1 }
      clipped_by { plane { x, 0.5 } } translate <-2, 0, 0> }
difference { box { -1, 1 } sphere { 0, 0.9 clipped_by { box { -1, <1, 0, 1> } } } translate 2 * x }
union { sphere { 0, 1 } cone { 0, 1, y, 0 } clipped_by { intersection { plane { y, 0.5 } plane { -y, 0.5 } } }
        bounded_by { clipped_by } translate <0, 0, 3> }
torus { 1, 0.3 bounded_by { box { -1.3, 1.3 } } clipped_by { bounded_by } inverse }
intersection { box { -1, 1 } sphere { 0, 1.2 } bounded_by { sphere { 0, 1.5 } } translate <0, 2, 2> }
