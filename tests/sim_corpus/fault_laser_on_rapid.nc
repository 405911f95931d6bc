G21 G90
M3 S600
G0 X10 Y10
G1 X20 F1000
G0 X50 Y50
M5
M2
; Planted fault: constant-power laser on during the rapids of lines 3 and 5 on a
; controller without laser mode.
; config grbl_laser_mode = false
; expect finding laser-on-rapid 3
; expect finding laser-on-rapid 5
; expect exit 1
