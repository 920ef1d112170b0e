%FUZZ.nc
[Found by the fuzz harness (a corpus program with its M30 line doubled): the second M30 was read]
[as a second program end, which the ISO output wrote twice and did not read back the same. M30]
[ends the program: the block after it is not run (HEIR009) and ENDE closes it.]
[Hand-derived: G97 500 rpm; G0 D40 Z2; G1 Z-20 at 0.25 mm/rev; M30 (spindle and coolant stop).]
BEARBEITUNG
N1 G97 S500 M3
N2 G0 X40 Z2
N3 G95 G1 Z-20 F0.25
N4 M30
N5 M30
ENDE
