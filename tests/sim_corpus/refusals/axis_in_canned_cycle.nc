(an A word in a canned cycle: LinuxCNC "Cannot put an a in canned cycle")
G21 G90 G94 F100
G0 Z5
G81 X0 Y0 Z-1 R1
A90
G80
M2
