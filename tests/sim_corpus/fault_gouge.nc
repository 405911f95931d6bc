G21 G90
G0 X9 Y9
M4 S500
G1 X31 Y9 F1000
G1 X31 Y20
G1 X30.5 Y31
G1 X9 Y31
G1 X9 Y9
M5
M2
; Planted fault: design square 10..30 kept outside with a 1 mm tool radius; the move of
; line 6 comes within 0.5 mm of the corner (30, 30).
; config tool_radius = 1.0
; design outside 10,10 30,10 30,30 10,30
; expect finding gouge 6
; expect exit 1
