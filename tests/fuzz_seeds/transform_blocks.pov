#declare T = transform { translate <1,2,3> rotate 30*y }
#declare U = transform { T inverse }
#declare V = transform T
camera { location <0,0,-10> look_at 0 transform { scale 1 } }
sphere { 0, 1 transform T transform U }
sphere { 0, 1 transform { T translate x } pigment { rgb 1 transform V } }
light_source { 0, 1 transform T }
