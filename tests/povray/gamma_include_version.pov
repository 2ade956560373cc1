// crosscheck: full 100
// A #version read in an include counts: colors.inc says #version 3.5 and
// then restores the version it found (3.7, POV-Ray's own until a scene
// sets one), so this scene follows 3.7's rules (assumed_gamma 1 implied,
// the sRGB curve in the file) although it never says #version.
#include "colors.inc"
camera { location <0, 1, -4> look_at 0 }
light_source { <5, 5, -5> color White }
sphere { 0, 1 pigment { color Orange } finish { phong 0.5 } }
plane { y, -1 pigment { checker color Gray30 color Gray70 } }
