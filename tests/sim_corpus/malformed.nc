; Malformed words become diagnostics with line and column; the rest still runs (a block
; with an unknown code is skipped, as LinuxCNC does).
; nolinuxcnc
; expect finding gcode-syntax 13
; expect finding gcode-syntax 14
; expect finding unknown-code 15
; expect finding gcode-syntax 16
; expect end 1 3 0 0
; expect end 2 3 4 0
; expect motions 3
; expect exit 1
G21 G90 F100
G1 X Y0
G1 X1 $2
G77 X2
G1 X3 (unclosed
G1 Y4
M2
