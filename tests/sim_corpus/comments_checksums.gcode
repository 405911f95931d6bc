; Comments of every kind, line numbers, % marks and RepRap checksums (one bad).
; nolinuxcnc (rs274 does not take * checksums)
; expect motions 3
; expect end 2 5 5 0
; expect finding bad-checksum 9
; expect exit 1
%
N1 G21 G90 (units) ; mm
N2 G0 X1 Y1*43
N3 G1 X5 Y1 F300*123
N4 ( move ) G1 X5 Y5 ; up
N5 M5
%
M2
