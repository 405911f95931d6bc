G21 G90
G0 X15 Y15
M4 S500
G1 X25 Y15 F1000
G1 X25 Y25
G1 X15 Y25
G1 X15 Y15
M5
G0 X5 Y5
M4
G1 X35 Y5
G1 X35 Y35
G1 X5 Y35
G1 X5 Y5
M5
M2
; Planted fault: the first contour (line 4 on) lies inside the design square 10..30 that
; must stay whole, far from its edges: only the side test sees it. The second is fine.
; config tool_radius = 1.0
; design outside 10,10 30,10 30,30 10,30
; expect finding gouge 4
; expect exit 1
