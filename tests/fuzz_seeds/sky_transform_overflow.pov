camera { location <0,0,-5> look_at 0 }
sky_sphere { pigment { gradient y color_map { [0 rgb 0] [1 rgb 1] } } scale 1e300 scale 1e300 }
sphere { 0, 1 pigment { rgb 1 } }
