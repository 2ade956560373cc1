// crosscheck: full 99.5
// phong on a perturbed normal: POV-Ray reflects the eye about the layer's
// normal as it is (ComputePhongColour), not along the reflected ray, which
// it turns back above the surface where strong bumps point it below (a
// ground seen at grazing angles, lit from behind:
// templates/Basic_Scenes/Night_moon_partly_cloudy.pov).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { angle 75 location <0, 1, -3> look_at <0, 1, 0> }
light_source { <-1000, 800, 3000> color rgb 1 }
plane { y, 0 texture { pigment { rgb <0.35, 0.65, 0> } normal { bumps 0.75 scale 0.015 }
                       finish { ambient 0.1 diffuse 0.9 phong 0.1 } } }
sphere { <1.2, 0.6, 1>, 0.6 pigment { rgb <0.8, 0.3, 0.2> } normal { bumps 1.5 scale 0.05 } finish { phong 0.8 phong_size 20 } }
