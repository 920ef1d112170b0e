%FEED.nc
[REFUSED: a feed before G94 or G95 (per revolution or per minute is the machine's setting)]
BEARBEITUNG
N1 G97 S600 M3
N2 G0 X20 Z2
N3 G1 Z-10 F0.2
ENDE
