// #39: export wrote a matrix the parser called singular (scale 1e-300)
#version 3.7;
sphere { 0, 1 pigment { checker scale 1e-300 } }
sphere { 0, 1 pigment { bozo scale <1e-300, 1, 1> rotate <10, 20, 30> } translate x }
