; A clean laser job: a rounded square (lines and IJ quarter arcs) and a full circle inside.
; expect motions 11
; expect exit 0
; expect clean
G21 G90 G17
G0 X10 Y0
M4 S800
G1 X40 F1500
G3 X50 Y10 I0 J10
G1 Y40
G3 X40 Y50 I-10 J0
G1 X10
G3 X0 Y40 I0 J-10
G1 Y10
G3 X10 Y0 I10 J0
M5
G0 X35 Y25
M4 S800
G2 X35 Y25 I-10 J0
M5
M2
