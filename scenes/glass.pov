// glass.pov — refraction: solid glass spheres of different ior, a glass
// slab (total internal reflection at grazing angles seen through its
// edge), a hollow glass shell (difference of two spheres) and a glass lens,
// over a striped floor made of boxes so the bending shows.
//
// Framed for 640x480 (4:3; default right 1.33).
#version 3.7;
#include "colors.inc"

global_settings { assumed_gamma 1.0 max_trace_level 10 }

camera {
    location <0, 3.5, -8>
    look_at <0, 0.8, 0>
    angle 50
}

light_source { <-4, 10, -6> color rgb <1, 1, 1> }
light_source { <6, 6, -4> color rgb <0.3, 0.3, 0.3> shadowless }
background { color rgb <0.2, 0.25, 0.35> }

#declare Glass = texture {
    pigment { color rgbf <1, 1, 1, 0.95> }
    finish { ambient 0 diffuse 0 specular 0.7 roughness 0.003 reflection 0.05 }
}

// floor: a white plane with dark stripes (thin boxes) to show the bending
plane { y, 0 pigment { color rgb <0.85, 0.85, 0.8> } finish { ambient 0.2 diffuse 0.7 } }
#declare Stripe = box { <-0.15, -1, -20>, <0.15, 0.01, 20> pigment { color rgb <0.1, 0.1, 0.3> } finish { ambient 0.2 diffuse 0.7 } }
object { Stripe translate <-4.5, 0, 0> }
object { Stripe translate <-3.5, 0, 0> }
object { Stripe translate <-2.5, 0, 0> }
object { Stripe translate <-1.5, 0, 0> }
object { Stripe translate <-0.5, 0, 0> }
object { Stripe translate <0.5, 0, 0> }
object { Stripe translate <1.5, 0, 0> }
object { Stripe translate <2.5, 0, 0> }
object { Stripe translate <3.5, 0, 0> }
object { Stripe translate <4.5, 0, 0> }
box { <-20, -1, 3>, <20, 0.012, 3.3> pigment { color rgb <0.7, 0.1, 0.1> } }

// solid spheres, ior 1.1 (weak) and 1.5 (glass)
sphere { <0, 0, 0>, 0.8 texture { Glass } interior { ior 1.1 } translate <-3.2, 0.8, 0> }
sphere { <0, 0, 0>, 0.8 texture { Glass } interior { ior 1.5 } translate <-1.3, 0.8, 0> }

// a hollow shell: the difference of two spheres (thin glass)
difference {
    sphere { <0, 0, 0>, 0.8 }
    sphere { <0, 0, 0>, 0.72 }
    texture { Glass }
    interior { ior 1.5 }
    translate <0.6, 0.8, 0>
}

// a thick glass slab on edge, turned: total internal reflection shows
// on its faces
box {
    <-0.9, 0, -0.15>, <0.9, 1.6, 0.15>
    texture { Glass }
    interior { ior 1.6 }
    rotate <0, -30, 0>
    translate <2.8, 0, 0.3>
}

// a plano-convex lens: a sphere cut by a box, lying flat in front
intersection {
    sphere { <0, -1.2, 0>, 1.5 }
    box { <-2, 0, -2>, <2, 1, 2> }
    texture { Glass }
    interior { ior 1.5 }
    translate <-0.2, 0.02, -2.3>
}
