// crosscheck: full
// data_files.pov: POV-Ray's data files (csg/lang/fileio.c), checked against
// POV-Ray 3.7 by tests/crosscheck_povray.sh (rendered as written by both):
// the spheres' centres, radii and colours are written to a file (floats,
// vectors, strings; a value with signs; an append), then read back until
// the file ends (#while (defined(F))), so each sphere is where, as large
// and of the colour that the written text says.  Framed for 160x120.
#version 3.7;

camera { location <0, 2, -10> look_at <0, 0.5, 0> angle 50 }
light_source { <5, 10, -8> color rgb 1 }
background { color rgb <0.1, 0.15, 0.25> }
plane { y, -1 pigment { checker color rgb 0.9, color rgb <0.3, 0.5, 0.3> } }

#fopen Out "data_files.txt" write
#for (I, 0, 3)
    #write (Out, <I * 2 - 3, I / 3, 0>, ",", 0.4 + I / 7, ",\n")
    #write (Out, "\"", str(I / 3, 0, 3), "\",\n")
#end
#fclose Out
#fopen Out "data_files.txt" append
#write (Out, "<+3.5, +-0.25, -2>, 0.6, \"0.9\"\n")  // (signs: any '+', then one '-')
#fclose Out

#fopen In "data_files.txt" read
#while (defined(In))
    #read (In, Centre, Radius, Shade)
    sphere { Centre, Radius
        pigment { color rgb <1, val(Shade), 1 - val(Shade)> }
        finish { phong 0.5 } }
#end
