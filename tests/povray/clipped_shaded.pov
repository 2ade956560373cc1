// crosscheck: full 99.5
// clipped_shaded.pov: clipped_by and bounded_by as POV-Ray 3.7 shades
// them, rendered as written by both programs: the clips' surfaces cast
// no shadow (light falls through the cut into an open hemisphere and
// onto the floor), the inside of a cut object is lit and shaded, a
// gated object (a bound smaller than it) casts the shadow POV-Ray's
// shadow rays give it.  Framed for 160x120.
#version 3.7;

camera { location <0, 5, -10> look_at <0, 0, 0> angle 55 }
light_source { <3, 12, -4> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

plane { y, -1 pigment { checker color rgb 0.9, color rgb <0.3, 0.5, 0.3> } }

// an open hemisphere: its bowl catches light through the missing top
sphere { 0, 1.3 clipped_by { plane { y, 0.3 } } translate <-2.5, 0, 0>
         pigment { color rgb <1, 0.4, 0.2> } finish { phong 0.5 } }
// a tube: a cylinder cut by an inverse thinner one and a slanted plane
cylinder { -y, 1.2 * y, 0.9 clipped_by { cylinder { -2 * y, 2 * y, 0.7 inverse } plane { y, 0.6 rotate z * -17 } }
           pigment { color rgb <0.3, 0.6, 1> } }
// a gated union: only the rays through its slab-shaped bound see it (and
// the shadow rays that meet the slab are blocked)
union { sphere { <-0.4, 0, 0>, 0.7 } sphere { <0.4, 0.3, 0>, 0.6 }
        bounded_by { box { <-2, -0.1, -2>, <2, 0.25, 2> } }
        translate <2.5, 0, 0> pigment { color rgb <1, 0.9, 0.3> } }
