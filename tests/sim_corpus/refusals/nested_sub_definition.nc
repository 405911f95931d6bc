(a subroutine defined inside another: LinuxCNC "Nested subroutine definition")
G21 G90 G94 F100
o100 sub
G1 X1
o200 sub
G1 Y1
o200 endsub
o100 endsub
o100 call
M2
