; R-format arcs: a short and a long CCW arc closing a circle, then a CW semicircle.
; expect motions 4
; expect end 1 50 60 0
; expect end 2 60 50 0
; expect end 3 80 50 0
; expect cut_length 94.24777960769379
; expect exit 0
G21 G90
G0 X60 Y50
M3 S300
G3 X50 Y60 R10 F600
G3 X60 Y50 R-10
M5
M3
G2 X80 Y50 R10
M5
M30
