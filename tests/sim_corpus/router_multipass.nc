G21 G90 G17
G0 Z5
G0 X20 Y20
M3 S12000
G4 P2
G1 Z-1 F300
G1 X60 F1200
G1 Y60
G1 X20
G1 Y20
G1 Z-2 F300
G1 X60 F1200
G1 Y60
G1 X20
G1 Y20
G0 Z5
G0 X100 Y40
G1 Z0 F300
G2 X100 Y40 Z-3 I-10 J0 F600
G2 X100 Y40 I-10 J0
G0 Z5
M5
M30
; A router pocket outline cut in two passes at z -1 and -2 (the second retraces the first),
; then a helical entry and a full circle: separate contours, no intersections.
; config kind = "router"
; config power_max = 24000.0
; config work_min = [0.0, 0.0, -20.0]
; expect motions 19
; expect exit 0
; expect clean
