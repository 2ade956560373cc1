// crosscheck: full 99
// prism { }: the four splines (linear with two outlines, the inner one a
// hole by the even-odd rule; quadratic; cubic; Bezier), linear_sweep and
// conic_sweep (from the apex, and from above it, upside down), heights
// given in either order, transformed; a prism in a difference.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -6> look_at <0, 0.5, 0> angle 50 }
light_source { <-5, 10, -10> color rgb 1 }
light_source { <4, 2, -6> color rgb 0.3 }
background { color rgb <0.1, 0.2, 0.3> }
prism { linear_sweep linear_spline 0, 1, 9,
  <-2, -1>, <-1, 1>, <-2.5, 1>, <-2, -1>, <-1.8, -0.5>, <-1.5, 0.6>, <-2.1, 0.7>, <-1.8, -0.5>,
  <-2, -1>
  pigment { color rgb <1, 0.3, 0.3> } }
prism { quadratic_spline 0.8, 0, 6, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>
  translate <-0.2, 0, 1.5> pigment { color rgb <0.3, 1, 0.3> } }
difference {
  prism { cubic_spline -0.5, 0.5, 7, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>, <0, 1>
    sturm rotate 20*x translate <1.8, 0.6, 0> pigment { color rgb <0.3, 0.3, 1> } }
  sphere { <1.8, 1.1, -0.6>, 0.5 pigment { color rgb 1 } }
}
prism { bezier_spline 0, 0.6, 8, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 1>, <-1, 1>, <-1, 0>, <0, 0>
  translate <0.3, 0, -1.5> pigment { color rgb <1, 1, 0.3> } finish { phong 0.5 } }
prism { conic_sweep quadratic_spline 0, 1, 6, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>
  scale 0.6 translate <-0.9, 0.2, -1.2> pigment { color rgb <0.3, 1, 1> } }
prism { conic_sweep linear_spline 0.25, 1, 5, <-1, -1>, <1, -1>, <0.5, 1>, <-0.5, 0.5>, <-1, -1>
  rotate 180*x translate <2.4, 1.2, -1.8> pigment { color rgb <1, 0.3, 1> } }
