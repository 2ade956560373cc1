// Macro arguments passed by reference: chained through two calls, an
// element, a #local at the body's end, and the caller's variable #undef'd
// while a parameter stands for it (the parameter keeps its copy).
#declare C = 1;
#declare A = array[2] {1, 2}
#macro Inner(W) #declare W = W + 1; #end
#macro Outer(V, B) Inner(V) #declare B[0] = V; #local V = V * 2; #end
Outer(C, A)
#macro Kill(V) #undef C #declare V = V + 1; #local Q = V; #end
#declare D = C;
Kill(C)
sphere { 0, D + A[0] }
