// crosscheck: full 99
// The extruded outlines, in one scene (each scene here costs make test
// several renders): text { ttf ... } (TrueType glyphs through FreeType,
// placed as POV-Ray places them: advance widths, the 'kern' table, the
// offset's x and y after each glyph, thickness along +z from 0, 1 em = 1
// unit; fonts from the library folders, one named without ".ttf"; a text
// in a difference, one turned so its curved walls show) and prism { } (the
// four splines, a hole by the even-odd rule, linear and conic sweeps,
// heights in either order, a prism in a difference).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0.6, 3.2, -6.5> look_at <0.6, 0.4, 0> angle 50 }
light_source { <-5, 10, -10> color rgb 1 }
light_source { <4, 2, -6> color rgb 0.3 }
background { color rgb <0.1, 0.2, 0.3> }
difference {
  text { ttf "cyrvetic" "Bag" 0.5, <0.05, 0.02, 0> pigment { color rgb <1, 0.6, 0.2> } }
  cylinder { <-1, 0.35, 0.25>, <3, 0.35, 0.25>, 0.12 pigment { color rgb <0.2, 0.9, 0.3> } }
  scale 1.2 rotate 30*x translate <-0.3, 0.9, 1.2>
}
text { ttf "timrom.ttf" "AVo%" 0.2, 0
  pigment { color rgb <0.9, 0.9, 1> } finish { phong 0.6 }
  scale 0.8 rotate <10, -40, 0> translate <1.6, 1.9, 0.8>
}
prism { linear_sweep linear_spline 0, 1, 9,
  <-2, -1>, <-1, 1>, <-2.5, 1>, <-2, -1>, <-1.8, -0.5>, <-1.5, 0.6>, <-2.1, 0.7>, <-1.8, -0.5>,
  <-2, -1>
  pigment { color rgb <1, 0.3, 0.3> } }
difference {
  prism { cubic_spline -0.5, 0.5, 7, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>, <0, 1>
    sturm rotate 20*x translate <2.6, 0.6, 0> pigment { color rgb <0.3, 0.3, 1> } }
  sphere { <2.6, 1.1, -0.6>, 0.5 pigment { color rgb 1 } }
}
prism { bezier_spline 0, 0.6, 8, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 1>, <-1, 1>, <-1, 0>, <0, 0>
  translate <0.3, 0, -1.5> pigment { color rgb <1, 1, 0.3> } finish { phong 0.5 } }
prism { conic_sweep quadratic_spline 1, 0, 6, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>
  scale 0.6 translate <-1.1, 0.2, -1.4> pigment { color rgb <0.3, 1, 1> } }
prism { conic_sweep linear_spline 0.25, 1, 5, <-1, -1>, <1, -1>, <0.5, 1>, <-0.5, 0.5>, <-1, -1>
  rotate 180*x translate <2.0, 1.2, -2.2> pigment { color rgb <1, 0.3, 1> } }
