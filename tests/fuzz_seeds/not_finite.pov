// #39: val() slipped past "not finite is an error" (an error at 5:14 now)
#version 3.7;
#declare A = array[3][2];
#declare N = dimension_size(A, 1e30) + val("2");
#declare B = val("nan");
sphere { 0, N + B }
