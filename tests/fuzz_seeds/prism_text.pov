// The two extruded outlines (csg/lang/outline.c): a prism of each spline
// and a text, for the fuzzer to vary.
camera { location <1, 1, -4> look_at <1, 0.4, 0> }
light_source { <-5, 10, -10> color rgb 1 }
prism { linear_spline 0, 1, 5, <0, 0>, <1, 0>, <0.5, 1>, <0.2, 0.5>, <0, 0> }
prism { quadratic_spline 0, 0.8, 6, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0> }
prism { cubic_spline -0.5, 0.5, 7, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>, <0, 1> }
prism { conic_sweep linear_spline 0.2, 1, 5, <0, 0>, <1, 0>, <0.5, 1>, <0.2, 0.5>, <0, 0> }
prism { bezier_spline 0, 0.6, 8, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 1>, <-1, 1>, <-1, 0>, <0, 0> }
difference { text { ttf "timrom.ttf" "Ag%" 0.3, <0.1, 0, 0> } box { 0, 0.5 } }
