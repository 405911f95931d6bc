G21 G90
G0 Z5
G0 X10 Y10
M3 S12000
G1 Z-2 F300
G1 X40 F1200
G0 X60 Y60
G0 Z5
M5
M2
; Planted fault: router rapid across the stock at cutting depth (line 7).
; config kind = "router"
; config safe_z = 5.0
; config power_max = 24000.0
; config work_min = [0.0, 0.0, -20.0]
; expect finding rapid-below-safe-z 7
; expect exit 1
