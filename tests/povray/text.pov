// crosscheck: full 99
// text { ttf ... }: TrueType glyphs through FreeType, placed as POV-Ray
// places them (advance widths, the 'kern' table, the offset vector's x and
// y after each glyph, thickness along +z from 0, 1 em = 1 unit); a font
// found in the library folders (Debian's povray-includes), one named
// without its ".ttf"; a text in a difference (a cylinder through the
// glyphs' bowls and holes) and one seen from the side (the curved walls).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <1.2, 1.0, -2.6> look_at <1.1, 0.3, 0> angle 55 }
light_source { <-5, 10, -10> color rgb 1 }
light_source { <5, 3, -3> color rgb 0.4 }
background { color rgb <0.1, 0.2, 0.3> }
plane { y, -0.25 pigment { checker rgb 0.8 rgb 0.4 } }
difference {
  text { ttf "cyrvetic" "Bag" 0.5, <0.05, 0.02, 0> pigment { color rgb <1, 0.6, 0.2> } }
  cylinder { <-1, 0.35, 0.25>, <3, 0.35, 0.25>, 0.12 pigment { color rgb <0.2, 0.9, 0.3> } }
}
text { ttf "timrom.ttf" "AVo%" 0.2, 0
  pigment { color rgb <0.9, 0.9, 1> } finish { phong 0.6 }
  scale 0.5 rotate <10, -40, 0> translate <1.2, 0.8, 0.3>
}
