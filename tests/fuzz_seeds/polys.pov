// #38: polys (quartic, cubic, poly of orders 2 to 7: order / 2 + 1
// pieces, unbounded, their coefficients in the blob's table), alone, cut
// by boxes, in CSG, inverse, transformed, sturm
#version 3.7;
camera { location <0, 3, -8> look_at 0 }
light_source { <3, 6, -4> color rgb 1 }
quartic { <1, 0, 0, 0, 2, 0, 0, 2, 0, -2.32, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
           1, 0, 0, 2, 0, 1.68, 0, 0, 0, 0, 1, 0, -2.32, 0, 0.7056> sturm rotate x * 60 }
intersection { cubic { <1, 0, 0, 0, -3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 0> } box { -1, 1 } translate x * 2 }
difference { box { -1, 1 } poly { 2, <1 0 0 0 1 0 0 1 0, -1> inverse scale 1.3 } translate <-3, 0, 4> }
poly { 7, <1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
           0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
           0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0,
           0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1>
      translate z * 6 pigment { color rgb 0.5 } }
