// clipped_union: a clipped union shows every child's surface inside the
// clip, those inside another child too (POV-Ray's union, then its clip):
// a wall and a floor (advanced/quilt1's stage), two overlapping spheres
// halved by a box (the inner halves of each show through the cut), and a
// union inside the clipped union.
#version 3.7;
camera { location <-5, 6, -13> angle 40 look_at <0, 0.5, 0> }
light_source { <10, 20, -2>, 1 }
background { rgb <0.3, 0.5, 0.8> }
union {
  plane { z, 0 pigment { checker rgb 1, rgb 0.3 } }
  plane { y, 0 inverse pigment { checker rgb <0.9, 0.8, 0.5>, rgb <0.3, 0.4, 0.6> } }
  clipped_by { box { <-4.9, -0.1, -10000>, <5.1, 1000, 1> } }
  rotate -y * 2
}
union {
  sphere { <-0.6, 1, -3>, 1 pigment { rgb <0.9, 0.2, 0.2> } }
  sphere { <0.6, 1, -3>, 1 pigment { rgb <0.2, 0.8, 0.3> } }
  union {
    sphere { <0, 1.2, -3.2>, 0.5 pigment { rgb <0.2, 0.3, 0.9> } }
    box { <-0.3, 0.2, -3.5>, <0.3, 0.6, -2.5> pigment { rgb <0.9, 0.9, 0.2> } }
  }
  clipped_by { box { <-2, 0, -10>, <2, 1.1, -3> } }
}
