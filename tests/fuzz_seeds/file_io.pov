// #fopen, #write, #read, #fclose, file_exists: a file written, then read back
#fopen Out "values.txt" write
#write (Out, "\"name\",", 1.5, ",", <1, 2, 3>, ",", <1, 0.5, 0, 0, 0>, ",\n")
#write (Out 2, "," -3 ",\n")
#fclose Out
#fopen Out "values.txt" append
#write (Out, "<4 5>, \"end\"")
#fclose Out
#fopen In "values.txt" read
#declare N = 0;
#while (defined(In))
  #undef Value  // (POV-Ray 3.7 reads into a colour or a 2-vector name no more)
  #read (In, Value)
  #declare N = N + 1;
#end
#fclose In
#if (file_exists("values.txt"))
  sphere { <N, 0, 0>, 1 pigment { rgb 1 } }
#end
camera { location <0, 0, -10> look_at 0 }
light_source { <5, 5, -5> color rgb 1 }
