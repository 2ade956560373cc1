// crosscheck: full 99.5
// prism_curved: the shading normals of a prism's curved sides, POV-Ray's
// Prism::Normal (the spline's, where the ray meets it; the conic sweep's
// with its height's component), not the chords' the sides are cut into:
// mirror-like prisms of the three curved splines, both sweeps, reflect a
// checker floor, whose cell edges show any tilt of the normal.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 4, -9> look_at <0, 0.9, 0> angle 40 }
light_source { <-6, 10, -8> color rgb 1 }
light_source { <6, 4, -6> color rgb 0.4 }
background { color rgb <0.2, 0.3, 0.5> }
plane { y, 0 pigment { checker color rgb <0.9, 0.8, 0.1> color rgb <0.1, 0.3, 0.8> scale 0.4 }
  finish { ambient 0.2 diffuse 0.8 } }
#declare Mirror = texture { pigment { color rgb <0.8, 0.8, 0.85> }
  finish { ambient 0.05 diffuse 0.2 reflection 0.7 specular 0.5 roughness 0.01 } }
// a Catmull-Rom loop, linear sweep
prism { cubic_spline 0, 2, 7, <0, -1>, <1, 0>, <0, 1>, <-1, 0>, <0, -1>, <1, 0>, <0, 1>
  texture { Mirror } translate <-2.4, 0, 0.5> }
// a quadratic loop, conic sweep, upside down
prism { quadratic_spline conic_sweep 0.4, 1, 6, <0, -1.2>, <1.2, 0>, <0, 1.2>, <-1.2, 0>,
  <0, -1.2>, <1.2, 0>
  texture { Mirror } rotate 180 * x scale <1, 2, 1> translate <0, 2, 0.3> }
// a Bezier lens, linear sweep
prism { bezier_spline 0, 1.6, 8, <-0.9, 0>, <-0.3, -0.9>, <0.3, -0.9>, <0.9, 0>,
  <0.9, 0>, <0.3, 0.9>, <-0.3, 0.9>, <-0.9, 0>
  texture { Mirror } rotate -30 * y translate <2.4, 0, 0> }
