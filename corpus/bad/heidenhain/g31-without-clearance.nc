%G31NOMODEL.nc
[REFUSED: G31 without the profile's g31_clearance (HEIR006): where the tool goes between]
[passes, and where the cycle starts and ends, is not published. The contour after the call]
[is passed over to G80, so N70 is read as the next move.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B4 P2 IC4 V0
N40 G0 X20 Z0
N50 G1 Z-30
N60 G80
N70 G0 X110 Z20
N80 M30
ENDE
