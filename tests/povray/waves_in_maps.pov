// crosscheck: full 99.5
// waves and ripples where no texture holds them: a pigment_map's entry,
// an average's entry, the sky_sphere's pigment (their wave sources are the
// scene's number_of_waves as a texture's are; a fuzzer's finding: the
// flattener left them 0 there, an invalid blob).
#version 3.7;
global_settings { assumed_gamma 1 number_of_waves 7 }
camera { location <0, 2.5, -6> look_at <0, 0.5, 0> }
light_source { <4, 8, -5>, 1 }
sky_sphere { pigment { ripples frequency 3 color_map { [0 rgb <0.2, 0.3, 0.6>] [1 rgb <0.8, 0.9, 1>] } } }
plane { y, 0
  pigment { checker pigment { waves frequency 2 color_map { [0 rgb 0.2] [1 rgb <1, 0.8, 0.4>] } }
                    pigment { rgb 0.7 } scale 1.37 } }
sphere { <-1.3, 1, 0>, 1
  pigment { average pigment_map { [1 waves scale 0.3] [2 ripples scale 0.2 color_map { [0 rgb <1, 0, 0>] [1 rgb <0, 0, 1>] }] } } }
sphere { <1.3, 1, 0>, 1
  pigment { gradient y pigment_map { [0 ripples frequency 4 scale 0.5] [1 rgb <0.3, 0.9, 0.3>] } } }
