// crosscheck: full 99.9
// poly_shaded.pov: polys as written (diffuse, phong, shadows cast on each
// other and on the floor), compared with POV-Ray 3.7 by colour: the
// normals (POV-Ray's Poly::Normal, the gradient in the poly's own frame
// carried to the world) and the shadow rays through a poly's pieces: a
// quartic torus (sturm), a cubic saddle and an order-5 poly cut by boxes,
// scaled and turned.  Framed for 160x120.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -9> look_at <0, 0.3, 0> angle 50 }
light_source { <-4, 9, -6> color rgb 1 }
light_source { <5, 4, -3> color rgb 0.4 }
plane { y, -1.2 pigment { color rgb <0.8, 0.8, 0.7> } }

// (x^2 + y^2 + z^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + z^2), R = 1, r = 0.4
quartic {
    <1, 0, 0, 0, 2, 0, 0, 2, 0, -2.32, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
     1, 0, 0, 2, 0, 1.68, 0, 0, 0, 0, 1, 0, -2.32, 0, 0.7056>
    sturm
    rotate x * 50 scale <1.2, 1, 0.9>
    pigment { color rgb <1, 0.4, 0.3> } finish { phong 0.6 phong_size 40 }
    translate <-2.6, 0.2, 0>
}
// x^3 - 3 x y^2 - z: the monkey saddle, cut by a box
intersection {
    cubic { <1, 0, 0, 0, -3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 0> }
    box { <-1, -1, -1>, <1, 1, 1> }
    rotate x * -90 rotate y * 20 scale 0.9
    pigment { color rgb <0.3, 0.6, 1> } finish { phong 0.5 }
    translate <0, 0, 0.5>
}
// x^5 + y^4 + z^4 - 0.5, cut by a box
intersection {
    poly { 5, <1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
               0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1,
               0, 0, 0, -0.5> }
    box { <-1.2, -1.2, -1.2>, <1.2, 1.2, 1.2> }
    rotate y * -30
    pigment { color rgb <1, 0.9, 0.4> } finish { phong 0.4 }
    translate <2.6, 0, 0>
}
