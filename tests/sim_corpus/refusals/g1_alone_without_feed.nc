(G1 with no axis word before any F: LinuxCNC "Cannot do g1 with zero feed rate")
G21 G90 G94
G0 X1 Y1
G1
M2
