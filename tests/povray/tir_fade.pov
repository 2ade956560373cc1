// crosscheck: full 99.5
// tir_fade: total internal reflection as POV-Ray's TraceRefractionRay does
// it: the ray reflected instead of the refracted one, its light faded by
// the interior (fade_distance, fade_power) but not filtered, and no
// reflection about the same normal besides; glass stacks with variable
// reflection (no fresnel) and conserve_energy (glass.inc's F_Glass9).
#version 3.7;
global_settings { assumed_gamma 1 max_trace_level 8 }
camera { location <0, 9, -14> look_at <0, 2.2, 0> angle 40 }
light_source { <10, 10, -5> * 1000, rgb 1.1 }
plane { y, 0 pigment { rgb 1 } finish { ambient 0.15 diffuse 0.8 } }
#declare Stack = merge {
  sphere { <0, 5, 0>, 1 }
  cone { y * 1.9, 1, y * 4.1, 0.5 }
  box { <-1.1, 0, -1.1>, <1.1, 2, 1.1> }
  translate 0.01 * y
}
#declare Glass = texture { pigment { rgbf <1, 1, 1, 1> }
  finish { specular 0.8 roughness 0.001 ambient 0 diffuse 0
           reflection { 0.05, 1.0 } conserve_energy } }
object { Stack texture { Glass }
  interior { ior 1.5 fade_distance 1 fade_power 2 fade_color <0.2, 0.3, 0.8> }
  translate -2.6 * x }
object { Stack texture { Glass }
  interior { ior 1.5 fade_distance 1 fade_power 1001 fade_color <0.2, 0.3, 0.8> } }
object { Stack texture { Glass finish { reflection 0.2 } }
  interior { ior 1.5 } translate 2.6 * x }
