// #39: crackle's cubes and the noise's cells overflowed int far away
#version -5555555555;
camera { location <2147483646.5, 0.3, -5> look_at <2147483646.5, 0.3, 0> }
light_source { <2147483646.5, 10, -10> color rgb 1 }
plane { z, 0 pigment { crackle solid } }
plane { -z, -1e30 pigment { bozo noise_generator 3 } }
