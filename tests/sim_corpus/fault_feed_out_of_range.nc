G21 G90
G0 X10 Y10
M4 S500
G1 X20 F1000
G1 X30 F9000
G1 X40
G1 X50 F1000
M5
M2
; Planted fault: F9000 on line 5 exceeds the 5000 mm/min limit (one finding for the run).
; expect finding feed-out-of-range 5
; expect exit 1
