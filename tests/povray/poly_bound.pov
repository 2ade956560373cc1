// poly_bound: POV-Ray keeps the bounded_by of a top-level poly, cubic or
// quartic (Link_To_Frame removes the bounds of cheap objects only): a
// bound smaller than the object hides it from the rays that miss the
// bound (objects/quartic/hyptorus's cut ends).
#version 3.7;
camera { location <0, 0, -20> angle 65 }
background { rgb 0.03 }
// a hyperbolic torus (major radius sqrt(40), minor sqrt(12)), its bound
// smaller than it
quartic {
  < 1.0,  0.0,  0.0,   0.0,    2.0,  0.0,  0.0, -2.0,  0.0, -104.0
    0.0,  0.0,  0.0,   0.0,    0.0,  0.0,  0.0,  0.0,  0.0,   0.0
    1.0,  0.0,  0.0,  -2.0,    0.0, 56.0,  0.0,  0.0,  0.0,   0.0
    1.0,  0.0, 104.0,  0.0,  784.0 >
  pigment { rgb <0.8, 0, 0.05> }
  bounded_by { sphere { 0, 14 } }
  rotate <90, 30, 0> rotate <10, 0, 0>
  translate 20 * z
}
// a poly (a sphere of radius 3, order 2) cut by a bound of radius 2.5
poly { 2, <1, 0, 0, 0, 1, 0, 0, 1, 0, -9>
  pigment { rgb <0.2, 0.6, 0.9> }
  bounded_by { sphere { 0, 2.5 } }
  translate <0, -6, 10>
}
