%ARC.nc
[REFUSED: an arc without the profile's arc_direction (the vendor shows G2's sense only in a graphic)]
BEARBEITUNG
N1 G97 S600 M3
N2 G0 X20 Z0
N3 G95 G2 X30 Z-5 I5 K0 F0.1
ENDE
