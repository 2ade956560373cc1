// ultra_wide_angle, 170 degrees
// The other camera types of POV-Ray (tracepixel.cpp's CreateCameraRay),
// objects all around the camera.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { ultra_wide_angle location <0, 2, 0> look_at <0, 1.5, 5> angle 170 }
light_source { <30, 50, -40> color rgb 1 }
background { rgb <0.3, 0.4, 0.6> }
plane { y, 0 pigment { checker rgb 0.9 rgb 0.25 } }
difference {
  box { <-1, 0, -1>, <1, 2, 1> pigment { rgb <0.9, 0.3, 0.2> } }
  sphere { <0, 2, -1>, 1.2 pigment { rgb <0.2, 0.8, 0.3> } }
  translate <0, 0, 5>
}
sphere { <4, 1, 1>, 1 pigment { rgb <0.2, 0.4, 0.9> } }
sphere { <-4, 1.5, 0>, 1.5 pigment { rgb <0.9, 0.8, 0.2> } }
cylinder { <0, 0, -5>, <0, 3, -5>, 0.8 pigment { rgb <0.7, 0.2, 0.8> } }
box { <-6, 0, -3>, <-5, 4, -2> pigment { rgb <0.2, 0.8, 0.8> } }
