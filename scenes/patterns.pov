// patterns.pov — POV-Ray 3.7's noise patterns: wood, marble, granite,
// agate, bozo, wrinkles and crackle, turbulence, the wave types and a
// pigment map (nested), on a floor, four balls and a box.  Every value is POV-Ray's own
// (workers/noise.c, tests/test_pigment.c).
//
// Framed for 640x480 (4:3; default right 1.33).
#version 3.7;

global_settings { assumed_gamma 1.0 }

camera {
    location <0, 4.2, -7.5>
    look_at <0, 0.6, 0>
    angle 52
}

light_source { <-4, 9, -6> color rgb <1, 1, 1> }
light_source { <5, 4, -8> color rgb <0.35, 0.35, 0.35> shadowless }
background { color rgb <0.55, 0.65, 0.8> }

// A wooden floor: planks of wood rings seen from the side.
plane {
    y, 0
    pigment {
        wood turbulence 0.08 octaves 4
        color_map { [0 rgb <0.85, 0.6, 0.35>] [0.7 rgb <0.6, 0.35, 0.17>] [1 rgb <0.45, 0.25, 0.1>] }
        scale <0.25, 0.25, 4> rotate 90 * y translate <0, 0, 0.3>
    }
    finish { diffuse 0.8 }
}

#declare Ball = sphere { 0, 0.9 }

object { Ball translate <-2.6, 0.9, 0.4>
    pigment { marble turbulence 1.4 color_map { [0 rgb 0.95] [0.8 rgb <0.4, 0.45, 0.5>] [1 rgb 0.1] } scale 0.6 }
    finish { phong 0.6 } }

object { Ball translate <-0.9, 0.9, 1.4>
    pigment { granite scale 1.5 color_map { [0 rgb <0.9, 0.75, 0.7>] [0.4 rgb <0.6, 0.3, 0.3>] [0.6 rgb 0.15] } }
    finish { phong 0.4 } }

object { Ball translate <0.9, 0.9, 1.4>
    pigment { agate agate_turb 0.6 scale 0.5 } }

object { Ball translate <2.6, 0.9, 0.4>
    pigment { bozo noise_generator 3 sine_wave frequency 3 scale 0.4
        color_map { [0 rgb <0.1, 0.3, 0.8>] [1 rgb <0.95, 0.9, 0.3>] } } }

// A pigment map: bands of wrinkles and of a checker of two pigments.
box {
    <-0.7, 0, -1.2>, <0.7, 1.1, 0.2>
    pigment {
        gradient y frequency 2
        pigment_map {
            [0.3 wrinkles scale 0.2 color_map { [0 rgb <0.2, 0.5, 0.2>] [1 rgb <0.8, 1, 0.6>] }]
            [0.7 checker pigment { rgb <0.9, 0.2, 0.1> }
                 pigment { crackle solid scale 0.15 color_map { [0 rgb <0.2, 0.2, 0.6>] [1 rgb 1] } }
                 scale 0.25]
        }
        turbulence 0.1
    }
    rotate 20 * y
}
