// checker_far: a checker floor to the horizon, rotated and stretched
// (incdemo/metals' stage), its cells far smaller than a pixel: each
// pixel's cell is decided by its own hit point, never pushed across a
// boundary it is merely near (the hit point's rounding in float).
#version 3.7;
camera { location <0, 20, -30> direction <0, 0, 1.75> right x * 1.33 look_at 0 * y }
plane { y, 0
  pigment { checker rgb 0.4, rgb 0.8 scale <1, 1, 10000> rotate y * 45 } }
