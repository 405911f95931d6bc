G21 G90
G0 X10 Y10
M4 S500
G1 X350 Y10 F1000
G1 X350 Y20
G1 X10 Y10
M5
M2
; Planted fault: line 4 leaves the 300 mm work area.
; expect finding out-of-bounds 4
; expect exit 1
