; Malformed words become diagnostics with line and column; the rest still runs.
; nolinuxcnc
; expect finding gcode-syntax 12
; expect finding gcode-syntax 13
; expect finding unknown-code 14
; expect finding gcode-syntax 15
; expect end 2 3 0 0
; expect end 3 3 4 0
; expect motions 4
; expect exit 1
G21 G90 F100
G1 X Y0
G1 X1 #1=2
G77 X2
G1 X3 (unclosed
G1 Y4
M2
