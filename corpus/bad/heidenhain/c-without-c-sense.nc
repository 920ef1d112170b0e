%C90.nc
[REFUSED: C90 without the profile's c_sense (with or against the spindle's turn is not published)]
BEARBEITUNG
N1 G97 S600 M3
N2 G0 X19 Z3
N3 G33 X19 Z-16 F2 B2 P2 C90 H0
ENDE
