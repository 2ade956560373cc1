// brick, hexagon, spiral1 and spiral2: their colour, pigment and texture
// lists, brick_size and mortar, the spirals' arms, as normals; far from
// the origin, where brick's and hexagon's cell arithmetic leaves int
camera { location <0, 2, -8> look_at 0 }
light_source { <4, 8, -6> color rgb 1 }
#declare B = pigment { brick rgb 1, rgb <0.6, 0.2, 0.1> brick_size <1, 0.5, 0.8> mortar 0.05 }
plane { y, -1 pigment { B brick pigment { hexagon } pigment { spiral2 4 } scale 0.3 } }
sphere { <-2, 0, 0>, 1 pigment { hexagon rgb 0.1, rgb 0.5 rgb 0.9 turbulence 0.4 } normal { brick 0.7 scale 0.2 } }
sphere { <0, 0, 0>, 1 pigment { spiral1 -3 frequency 2 sine_wave turbulence 0.2 } normal { spiral2 5, 1.2 } }
box { <1, -1, -1>, <3, 1, 1> texture { hexagon texture { pigment { rgb 1 } } texture { pigment { B } } scale 0.4 } }
box { <1, 1.2, -1>, <3, 2, 1> normal { checker 0.5 } }
plane { z, 3e12 pigment { brick brick_size 1e-9 mortar 1e-10 } }
plane { x, -4e15 pigment { hexagon scale 1e-12 } }
