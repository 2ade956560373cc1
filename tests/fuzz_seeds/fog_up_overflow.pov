camera { location <0,0,-5> look_at 0 }
fog { fog_type 2 distance 3 fog_offset 0.5 fog_alt 0.5 rgb 1 scale 1e300 scale 1e300 }
sphere { 0, 1 pigment { rgb 1 } }
plane { y, -1 pigment { rgb 0.5 } }
