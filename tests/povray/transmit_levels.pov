// crosscheck: full 99.5
// transmit_levels: a ray that goes through a surface with the same ior on
// both sides (no interior: ior 1) goes on as POV-Ray's continued ray, its
// trace level not raised: six filtering sheets in a row, max_trace_level
// 3, show the wall behind them; a refracting sphere (ior 1.5) counts its
// levels as before.
#version 3.7;
global_settings { assumed_gamma 1 max_trace_level 3 }
camera { location <0, 2, -8> look_at <0, 1, 0> }
light_source { <3, 8, -6>, 1 }
plane { z, 3 pigment { checker rgb <0.9, 0.8, 0.3>, rgb <0.2, 0.3, 0.7> } }
plane { y, 0 pigment { rgb 0.6 } }
#declare I = 0;
#while (I < 6)
  box { <-3, 0, -1.5 + I * 0.4>, <0.5, 2.5, -1.45 + I * 0.4>
    pigment { rgbf <0.95, 1, 0.9, 0.9> } finish { ambient 0.05 diffuse 0.1 phong 0.5 } }
  #declare I = I + 1;
#end
sphere { <1.8, 1, -1>, 0.9
  pigment { rgbf <1, 1, 1, 0.9> } finish { ambient 0 diffuse 0.1 reflection 0.1 }
  interior { ior 1.5 } }
