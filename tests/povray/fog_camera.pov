// crosscheck: full 99.5
// The camera inside a non-hollow object: no fog until the ray leaves it
// (POV-Ray's primary rays start with the interiors around the camera);
// a hollow one around it changes nothing; fog_type 2 with a bare distance.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 1.5, -6> look_at <0, 1, 0> }
light_source { <5, 10, -5> color rgb 1 }
background { rgb <0.2, 0.3, 0.5> }
fog { 10 color rgb <0.8, 0.8, 0.85> }
sphere { <0, 1.5, -6>, 3 pigment { rgbf <1, 1, 1, 0.95> } finish { ambient 0 diffuse 0 } }
box { <-20, -20, -20>, <20, 20, 20> pigment { rgbt 1 } hollow }
plane { y, 0 pigment { checker rgb 0.8 rgb 0.3 } }
sphere { <-1.5, 1, 2>, 1 pigment { rgb <0.9, 0.3, 0.2> } }
sphere { <1.5, 1, 6>, 1 pigment { rgb <0.2, 0.8, 0.3> } }
