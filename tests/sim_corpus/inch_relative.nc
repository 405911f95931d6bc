; Inch units and relative distances; expected end points in mm.
; expect motions 4
; expect end 0 25.4 25.4 0
; expect end 1 50.8 25.4 0
; expect end 2 50.8 50.8 0
; expect end 3 0 0 0
; expect cut_length 86.72102448427661
; expect exit 0
G20 G91 G17
M4 S500
G1 X1 Y1 F10
X1
Y1
G90 M5
G0 X0 Y0
M2
