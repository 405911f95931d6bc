G21 G90
G0 X10 Y10
M4 S500
G1 X30 Y10 F1000
G1 X30 Y30
G1 X10 Y30
G1 X10 Y10
M5
G0 X20 Y20
M4
G1 X40 Y20
G1 X40 Y40
G1 X20 Y40
G1 X20 Y20
M5
M2
; Planted fault: two squares whose outlines cross (lines 5/11 and 6/14).
; expect finding contour-crossing 5 11
; expect finding contour-crossing 6 14
; expect exit 1
