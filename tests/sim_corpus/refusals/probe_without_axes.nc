(G38.2 probe with no axis word: LinuxCNC "All axes missing with motion code")
G21 G90 G94 F100
G38.2
M2
