// crosscheck: full 99.5
// shadowless_highlights: a shadowless light (POV-Ray's fill light) lights
// diffusely but gives no phong or specular highlight; the shadowed light
// beside it gives both.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 3, -7> look_at <0, 0.8, 0> }
light_source { <-6, 8, -6>, rgb <0.5, 0.5, 0.45> }
light_source { <5, 6, -8>, rgb <0.8, 0.8, 0.9> shadowless }
// (a plain floor: a checker to the horizon is float-limited at grazing
// incidence, bench/POVRAY_DIFFERENCES.md, checker boundaries)
plane { y, 0 pigment { rgb 0.5 } finish { phong 0.8 phong_size 5 } }
sphere { <-1.4, 1, 0>, 1
  pigment { rgb <0.8, 0.3, 0.2> } finish { phong 1 phong_size 8 } }
sphere { <1.4, 1, 0>, 1
  pigment { rgb <0.2, 0.5, 0.8> } finish { specular 0.9 roughness 0.08 metallic } }
