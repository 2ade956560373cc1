// The fuzzer's finding (2026-11-30): waves in a pigment_map's entry (no
// texture of its own) flattened with no wave sources, a blob the
// validator refused ("the flattener wrote an invalid blob").
#version 3.7;
camera { location <0, 3, -8> look_at 0 }
light_source { <3, 6, -4> color rgb 1 }
sphere { 0, 1 pigment { average pigment_map { [1 waves] [3 bozo scale 0.2] } } }
sky_sphere { pigment { ripples } }
