G21 G90
G0 X10 Y10
M4 S500
G1 X30 Y30 F1000
G1 X30 Y10
G1 X10 Y30
G1 X10 Y10
M5
M2
; Planted fault: a bow-tie contour, segment of line 4 crosses that of line 6.
; expect finding self-intersection 4 6
; expect exit 1
