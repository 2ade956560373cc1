// bounded_by.pov: POV-Ray's bounded_by when the bound does not enclose
// the object, checked against POV-Ray 3.7 by tests/crosscheck_povray.sh.
// A bound does not clip (POV-Ray's Ray_In_Bound): a ray that meets the
// bound anywhere, or starts inside it, sees the whole object; one that
// misses it sees none of it.  POV-Ray keeps the bound of CSG (a union
// here is not split), of a CSG child (its surfaces only: the solid still
// cuts), and removes it from a top-level sphere ("Unnecessary bounding
// object removed"): that sphere shows whole.  No floor: nothing behind
// that POV-Ray's bounding hierarchy could test first.  Framed for 160x120.
#version 3.7;

camera { location <0, 3, -12> look_at <0, 0.5, 0> angle 60 }
light_source { <5, 10, -8> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }

// a union bounded by a thin slab: only the rays through the slab see it
union {
    sphere { <-0.6, 0, 0>, 1 } sphere { <0.6, 0, 0>, 1 }
    bounded_by { box { <-3, -0.2, -3>, <3, 0.2, 3> } }
    translate <-4, 0, 0> pigment { color rgb <1, 0.3, 0.2> } }
// two bounds: both must be met
intersection {
    box { -1, 1 } sphere { 0, 1.3 }
    bounded_by { box { <-1, -1, -3>, <0.3, 1, 3> } plane { y, 0.4 } }
    rotate y * 30 translate <-1, 0, 0> pigment { color rgb <0.2, 0.6, 1> } }
// a child's bound hides its surfaces, not its solid
difference {
    box { <-1, -1, -1>, <1, 1, 1> }
    sphere { <0, 0, -1>, 0.8 bounded_by { box { <-0.2, -2, -2>, <2, 2, 2> } } }
    rotate y * -20 translate <1.8, 0, 0> pigment { color rgb <1, 0.5, 1> } }
// a sphere's bound is removed: the whole sphere shows
sphere { 0, 1 bounded_by { box { -0.1, 0.1 } } translate <4.5, 0, 0> pigment { color rgb <1, 1, 0.3> } }
// a bound with its own clip; a bound that is CSG
merge {
    cylinder { -y, y, 0.6 } sphere { y, 0.7 }
    bounded_by { sphere { 0, 1.4 clipped_by { plane { x, 0 } } } }
    translate <-3, 2.7, 3> pigment { color rgb <0.6, 1, 0.4> } }
union {
    box { -0.8, 0.8 } cone { -1.5 * y, 1, 1.5 * y, 0 }
    bounded_by { difference { sphere { 0, 1.2 } box { <0, -2, -2>, <2, 0, 2> } } }
    rotate y * 20 translate <2, 2.7, 3> pigment { color rgb <1, 0.7, 0.2> } }
// a bound met only through its own clip's cut is not met (Ray_In_Bound
// finds no intersection of the bound: the cut is no surface): hidden
union {
    sphere { 0, 0.5 } sphere { <0.4, 0, 0>, 0.4 }
    bounded_by { sphere { 0, 4 clipped_by { box { <-5, -5, -0.3>, <5, 5, 0.3> } } } }
    translate <0, -1.8, -4> pigment { color rgb <0.8, 0.8, 0.8> } }
