// lattice.pov — a CSG lattice written with the language's loops and
// macros: #macro with parameters and #local, #for and #while, #if and
// #switch, arrays, seed/rand, strings and #error, image_width/image_height, and the
// checker and gradient pigments.
//
// Framed for 640x480 (4:3; right x*image_width/image_height).
//
// N x N x N joints (rounded cubes: box ∩ sphere, the macro Joint) joined by
// struts along x, y and z (the macro Strut, one call a lattice edge, from
// three nested #for loops); the joints take their colour from an array by
// the parity of their lattice coordinates (#switch), the struts a gradient
// along their own axis (the pigment turns with the strut).  A second,
// smaller lattice stands beside it, each joint moved a little by POV-Ray's
// random numbers (seed 7: the same scene every time, in POV-Ray too).  The
// floor is a checker.
#version 3.7;

global_settings { assumed_gamma 1.0 }

#declare N = 4;           // joints along each axis
#declare Step = 1.0;      // distance between joints
#declare Radius = 0.06;   // of the struts

#declare Palette = array[3] {
    color rgb <0.85, 0.30, 0.15>,
    color rgb <0.20, 0.55, 0.85>,
    color rgb <0.90, 0.80, 0.25>
}

#declare StrutPigment = pigment {
    gradient x
    color_map {
        [0.0 color rgb <0.9, 0.9, 0.9>]
        [0.5 color rgb <0.3, 0.3, 0.35>]
        [1.0 color rgb <0.9, 0.9, 0.9>]
    }
}

// A rounded cube of half-size S at P, coloured by the lattice cell (I, J, K).
#macro Joint(P, S, I, J, K)
    #local C = Palette[mod(I + J + K, 3)];
    #switch (mod(I + 2 * J + K, 3))
        #case (0)
            #local F = finish { phong 0.6 phong_size 60 }
            #break
        #case (1)
            #local F = finish { specular 0.4 roughness 0.02 }
            #break
        #else
            #local F = finish { diffuse 0.7 }
    #end
    intersection {
        box { -S, S }
        sphere { 0, S * 1.35 }
        pigment { C }
        finish { F }
        translate P
    }
#end

// A strut from A to B: a cylinder whose gradient runs along it.
#macro Strut(A, B)
    #local L = vlength(B - A);
    cylinder {
        0, L * x, Radius
        pigment { StrutPigment scale L }
        #if (abs(B.y - A.y) > 0) rotate 90 * z #end
        #if (abs(B.z - A.z) > 0) rotate -90 * y #end
        translate A
    }
#end

// One lattice: its joints and, from each joint, the struts to its
// neighbours along +x, +y and +z.
#macro Lattice(Origin, Jitter, Seed)
    #local R = seed(Seed);
    union {
        #for (I, 0, N - 1)
            #for (J, 0, N - 1)
                #local K = 0;
                #while (K < N)
                    #local P = Origin + Step * <I, J, K>;
                    #local D = Jitter * <rand(R) - 0.5, rand(R) - 0.5, rand(R) - 0.5>;
                    Joint(P + D, 0.15, I, J, K)
                    #if (I < N - 1) Strut(P, P + Step * x) #end
                    #if (J < N - 1) Strut(P, P + Step * y) #end
                    #if (K < N - 1) Strut(P, P + Step * z) #end
                    #local K = K + 1;
                #end
            #end
        #end
    }
#end

#declare Name = concat("lattice ", str(N, 0, 0), "x", str(N, 0, 0), "x", str(N, 0, 0));
#if (Name != "lattice 4x4x4") // a string check; #debug Name would print it
    #error concat("unexpected ", Name)
#end

camera {
    location <7.5, 5.5, -7.5>
    right x * image_width / image_height
    look_at <0.6, 1.1, 0.4>
    angle 52
}

light_source { <10, 15, -12> color rgb <1, 1, 1> }
light_source { <-8, 6, -4> color rgb <0.35, 0.35, 0.4> shadowless }
background { color rgb <0.10, 0.12, 0.18> }

plane {
    y, -0.25
    pigment { checker color rgb <0.75, 0.75, 0.72> color rgb <0.35, 0.38, 0.42> scale 0.75 }
    finish { ambient 0.15 diffuse 0.7 }
}

object { Lattice(<0, 0, 0>, 0, 1) }
object { Lattice(<0, 0, 0>, 0.2, 7) scale 0.45 translate <-1.2, 0, -3.2> }
