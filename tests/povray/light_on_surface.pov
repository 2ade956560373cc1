// crosscheck: full 99.5
// A light on a surface: POV-Ray's shadow rays ignore what lies within
// 1e-3 of the light (SHADOW_TOLERANCE), so the cylinder's cap and the
// box's face that hold the lights do not shadow the floor in front of them
// (they did where rounding put the face before the light: speckles;
// lights/laser.pov).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <-3, 4, -9> look_at <0, -0.5, -1> }
light_source { <-1.5, 0.3, -1.3> color rgb <1, 0.3, 0.2> spotlight point_at <-1.5, -1, -8> radius 40 falloff 60 }
light_source { <1.7, 0.1, -1.1> color rgb <0.2, 0.6, 1> spotlight point_at <1.7, -1, -8> radius 40 falloff 60 }
light_source { <2, 9, -3> color rgb 0.3 }
plane { y, -1 pigment { rgb 0.8 } }
cylinder { <-1.5, 0.3, -1.3>, <-1.5, 0.3, 3.7>, 0.5 pigment { rgb <1, 0.5, 0.4> } }
box { <1.2, -1, -1.1>, <2.4, 1.1, 1.3> pigment { rgb <0.5, 0.7, 1> } }
