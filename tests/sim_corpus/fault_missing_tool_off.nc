G21 G90
G0 X10 Y10
M4 S500
G1 X20 F1000
G1 Y20
; Planted fault: the file stops with the laser on, no M5 and no M2 (truncated).
; expect finding tool-on-at-end 5
; expect finding missing-program-end 5
; expect exit 1
