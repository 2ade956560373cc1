// #38: quadrics (two pieces, maybe unbounded, transformed into world
// coefficients), alone, cut by boxes, in CSG, inverse
#version 3.7;
camera { location <0, 3, -8> look_at 0 }
light_source { <3, 6, -4> color rgb 1 }
quadric { <1, 4, 2>, <0, 0, 0>, <0, 0, 0>, -1 rotate z * 30 }
intersection { quadric { <1, -1, 1>, <0.4, 0, 0>, <0, 0, 0>, -0.3 } box { -1, 1 } translate x * 2 }
quadric { <1, 0, 1>, <0, 0, 0>, <0, -1, 0>, 0 scale <1, 2, 1> translate <-3, 0, 4> }
difference { sphere { 0, 1 } quadric { <0, 1, 0>, <0, 0, 0>, <0, 0, 0>, -0.25 inverse } translate z * 3 }
quadric { <0, 0, 0>, <0, 0, 0>, <0, 1, 0>, 1 pigment { color rgb 0.5 } }
