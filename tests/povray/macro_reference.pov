// crosscheck: full 99.5
// A macro argument that is one identifier alone is passed by reference:
// the macro's #declare of its parameter turns the caller's object (the
// cyan and yellow cones point at the camera and sideways), a #local of a
// parameter changes the caller's float (the box's height), an expression
// argument (object { Copy }) is a copy: the red cone stays upright; the
// declaration that ends the body binds the parameter
// (language/macros/macro2.pov).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <3, 3, -10> angle 35 look_at 0 }
light_source { <1000, 1000, -1000> color rgb 1 }
plane { y, -2 pigment { checker rgb 0.9 rgb 0.5 } }
#macro Turn_Me(Stuff, Degrees, Axis)
    #declare Stuff = object { Stuff rotate Axis * Degrees }
#end
#macro Double(V) #local V = 2 * V; #end
#declare Thing = cone { 0, 1/2, y, 0 }
#declare Copy = Thing;
Turn_Me(object { Copy }, 90, x)
object { Copy pigment { rgb <1, 0, 0> } translate -2.25 * x }
Turn_Me(Thing, -90, x)
object { Thing pigment { rgb <0, 1, 1> } }
Turn_Me(Thing, -90, y)
object { Thing pigment { rgb <1, 1, 0> } translate 2.25 * x }
#declare H = 0.4;
Double(H)
box { <-0.4, -2, 1>, <0.4, -2 + H, 1.8> pigment { rgb <0.2, 0.3, 1> } }
