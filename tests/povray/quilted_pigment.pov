// The quilted pattern as a pigment: its control0 and control1 (POV-Ray's
// defaults 1 and 1, and others) shape the value (POV-Ray's quilt_cubic);
// they reached only a normal's quilted before (a pigment read 0 and 0).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 0, -6> look_at 0 }
light_source { <3, 5, -8> color rgb 1 }
#declare Q = color_map { [0 rgb <0.1, 0.1, 0.3>] [0.5 rgb <0.9, 0.6, 0.2>] [1 rgb 1] }
box { <-2.6, -1.9, 0>, <-0.1, 1.9, 1> pigment { quilted color_map { Q } scale 0.4 } }
box { <0.1, -1.9, 0>, <2.6, -0.1, 1> pigment { quilted control0 0.2 control1 0.8 color_map { Q } scale 0.4 } }
sphere { <1.35, 0.95, 0>, 0.9 pigment { quilted control0 -1 control1 2 color_map { Q } scale 0.3 rotate <20, 30, 0> } }
