// crosscheck: full 100
// POV-Ray's legacy gamma mode: no #version and no assumed_gamma, so the
// effective version is 3.62 and the colours are written to the file as they
// are (no gamma correction); a transparent sphere dims by 3.6's formula
// (1 - filter * max(rgb) - transmit); the background's transmit is dropped.
camera { location <0, 1, -4> look_at 0 }
light_source { <5, 5, -5> color rgb 1 }
background { rgbt <0.2, 0.3, 0.4, 0.5> }
sphere { <-0.6, 0, 0>, 0.8 pigment { rgb <0.8, 0.4, 0.2> } finish { phong 0.5 } }
sphere { <0.9, 0, 0.5>, 0.7 pigment { rgbf <0.3, 0.9, 0.5, 0.6> } }
plane { y, -1 pigment { checker rgb 0.3 rgb 0.7 } }
