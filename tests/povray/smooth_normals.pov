// crosscheck: full 99.5
// Smooth triangles whose vertex normals point against their winding (as
// chess.inc's do): POV-Ray turns the interpolated normal towards the ray by
// its own direction, so the surface shades smoothly.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2, -5> look_at <0, 0.3, 0> }
light_source { <4, 6, -6> color rgb 1 }
background { rgb 0.1 }
#declare R = 1.2;
mesh {
    #for (I, 0, 11)
        #declare A0 = I * 30;
        #declare A1 = (I + 1) * 30;
        #declare P0 = <R * sin(radians(A0)), 0, R * cos(radians(A0))>;
        #declare P1 = <R * sin(radians(A1)), 0, R * cos(radians(A1))>;
        #declare Q0 = <0.6 * sin(radians(A0)), 1.2, 0.6 * cos(radians(A0))>;
        #declare Q1 = <0.6 * sin(radians(A1)), 1.2, 0.6 * cos(radians(A1))>;
        // normals pointing into the shape, the winding facing out
        smooth_triangle { P0, -vnormalize(P0 + y * 0.5), P1, -vnormalize(P1 + y * 0.5),
                          Q0, -vnormalize(Q0 + y * 0.8) }
        smooth_triangle { P1, -vnormalize(P1 + y * 0.5), Q1, -vnormalize(Q1 + y * 0.8),
                          Q0, -vnormalize(Q0 + y * 0.8) }
    #end
    pigment { rgb <0.9, 0.7, 0.3> }
    finish { phong 0.6 phong_size 30 }
}
plane { y, 0 pigment { checker rgb 0.2 rgb 0.6 } }
